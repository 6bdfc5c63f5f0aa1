//! Vector arithmetic in `f64` for the loaders: normals and camera axes are
//! worked out in double precision from the `f32` input, so that nearly
//! parallel or tiny vectors are judged on accurate values.

/// `v` in `f64`.
pub(crate) fn widen(v: [f32; 3]) -> [f64; 3] {
    v.map(f64::from)
}

/// `a - b`.
pub(crate) fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// The cross product `a x b`.
pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The dot product `a . b`.
pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The Euclidean length of `v`.
pub(crate) fn length(v: [f64; 3]) -> f64 {
    dot(v, v).sqrt()
}
