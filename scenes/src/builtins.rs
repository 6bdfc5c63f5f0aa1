//! Built-in meshes and scenes.
//!
//! Meshes are generated on demand, deterministically: the Utah teapot
//! tessellated from Newell's Bezier patches, an icosphere, a procedural
//! starfighter, a lumpy closed blob and a cube. Scenes put one of them (or a
//! few spheres) in front of a camera that frames them, with one directional
//! light.
//!
//! Every mesh is wound counter-clockwise when seen from outside (OpenGL front
//! faces) and has one unit normal per vertex.

mod blob;
mod geom;
pub mod overdraw;
mod random;
mod shapes;
mod starfighter;
pub mod synthetic;
mod teapot;
mod teapot_data;

use crate::openings::mesh_openings;
use crate::scene_desc::{CameraDesc, LightDesc, MeshData, ObjectDesc, SceneDesc, ShadingDesc};
use geom::{add, cross, dot, mul, normalize, sub, Mat3, V3};

/// Names of the built-in scenes.
pub const BUILTIN_SCENES: &[&str] = &[
    "teapot",
    "spheres",
    "starfighter",
    "layers",
    "grid",
    "knot",
    "overdraw",
    "blob",
];

/// Names of the built-in meshes, as accepted by [`builtin_mesh`] (besides
/// the `teapot:N` and `sphere:N` forms).
pub const BUILTIN_MESHES: &[&str] = &[
    "teapot",
    "sphere",
    "starfighter",
    "blob",
    "cube",
    "grid",
    "knot",
];

/// The light of every built-in scene: from above, right and in front, with
/// a moderate highlight.
pub const BUILTIN_LIGHT: LightDesc = LightDesc {
    direction: [0.4, 0.7, 1.0],
    ambient: 0.15,
    diffuse: 0.75,
    specular: 0.4,
    shininess: 24.0,
};

/// Teapot tessellation (segments per patch side) when none is given.
pub const DEFAULT_TEAPOT_TESSELLATION: u32 = 8;

/// Largest accepted teapot tessellation.
pub const MAX_TEAPOT_TESSELLATION: u32 = 64;

/// Icosphere subdivision level when none is given.
pub const DEFAULT_SPHERE_LEVEL: u32 = 3;

/// Largest accepted icosphere subdivision level.
pub const MAX_SPHERE_LEVEL: u32 = 8;

const KNOWN_MESHES: &str = "teapot, teapot:N (N = 1..=64), sphere, sphere:N (N = 1..=8), \
    starfighter, blob, cube, grid[:N] (N = 1..=1024), knot[:SEGMENTS[:SIDES]]";

/// A built-in mesh by name.
///
/// Names: `teapot` (tessellation 8), `teapot:N` (N = segments per Bezier
/// patch side, 1..=64; `32 * N * N * 2` triangles), `sphere` (unit
/// icosphere, level 3), `sphere:N` (N = 1..=8 levels; `20 * 4^N`
/// triangles), `starfighter`, `blob` (a lumpy closed surface, 3,700
/// triangles), `cube` (the cube [-1, 1]^3, 12 triangles),
/// `grid:N` (a wavy height field over [-1, 1]^2 of the XZ plane, `2 N^2`
/// triangles) and `knot:SEGMENTS:SIDES` (a (2, 3) torus knot tube within
/// radius 1, `2 SEGMENTS SIDES` triangles); see [`synthetic`] for their
/// defaults. A leading `builtin:` is ignored, so the `mesh_name` of a
/// built-in scene's single-mesh objects is accepted too.
///
/// The teapot sits around the origin within radius 1, lid towards +Y and
/// spout towards +X; the starfighter has its nose towards -Z and lies within
/// radius 1.5; the blob lies between radius 0.75 and 1.15 around the origin.
pub fn builtin_mesh(name: &str) -> Result<MeshData, String> {
    let bare = name.strip_prefix("builtin:").unwrap_or(name);
    let (base, arg) = match bare.split_once(':') {
        Some((base, arg)) => (base, Some(arg)),
        None => (bare, None),
    };
    match (base, arg) {
        ("teapot", arg) => {
            let n = parse_param(
                name,
                arg,
                DEFAULT_TEAPOT_TESSELLATION,
                MAX_TEAPOT_TESSELLATION,
            )?;
            Ok(teapot::teapot(n))
        }
        ("sphere", arg) => {
            let level = parse_param(name, arg, DEFAULT_SPHERE_LEVEL, MAX_SPHERE_LEVEL)?;
            Ok(shapes::icosphere(level))
        }
        ("starfighter", None) => Ok(starfighter::starfighter()),
        ("blob", None) => Ok(blob::blob()),
        ("cube", None) => Ok(shapes::cube()),
        ("grid" | "knot", _) => synthetic::synthetic_mesh(bare).ok_or_else(|| {
            format!("built-in mesh '{name}': bad parameters (known: {KNOWN_MESHES})")
        }),
        _ => Err(format!(
            "unknown built-in mesh '{name}' (known: {KNOWN_MESHES})"
        )),
    }
}

/// The `N` of `name:N`, within `1..=max`, or `default` without one.
fn parse_param(name: &str, arg: Option<&str>, default: u32, max: u32) -> Result<u32, String> {
    let Some(arg) = arg else {
        return Ok(default);
    };
    match arg.trim().parse::<u32>() {
        Ok(n) if (1..=max).contains(&n) => Ok(n),
        _ => Err(format!(
            "built-in mesh '{name}': '{arg}' is not a number in 1..={max} (known: {KNOWN_MESHES})"
        )),
    }
}

/// A built-in scene by name at the given image size: `teapot` (also
/// `teapot:N` for another tessellation), `spheres`, `starfighter`, `blob`
/// (the lumpy closed mesh, back faces culled, Gouraud shading), or one of
/// the synthetic scenes `layers:N:DEPTH:SEED`, `grid:N` and
/// `knot:SEGMENTS:SIDES` (see [`synthetic`]), or `overdraw:N:SEED` (many
/// overlapping cubes and coarse spheres, see [`overdraw`]). `None` for an
/// unknown name or bad parameters.
///
/// Each scene has one directional light, a dark background and a camera
/// looking slightly down at the object(s), which fill about three quarters
/// of the image.
pub fn builtin_scene(name: &str, width: u32, height: u32) -> Option<SceneDesc> {
    let bare = name.strip_prefix("builtin:").unwrap_or(name);
    let mut toward_eye = [0.0, 0.38, 1.0];
    let objects = match bare {
        "spheres" => spheres_objects(),
        "starfighter" => vec![ObjectDesc {
            // Every part is closed: faces turned away are hidden anyway.
            cull_backfaces: true,
            ..object(
                "builtin:starfighter",
                builtin_mesh("starfighter").ok()?,
                [200, 205, 210],
                [-20.0, 145.0, 0.0],
            )
        }],
        "blob" => vec![ObjectDesc {
            // Closed, and shaded the cheap way: the scene for comparing speed
            // with renderers that do not antialias.
            cull_backfaces: true,
            shading: Some(ShadingDesc::Gouraud),
            ..object(
                "builtin:blob",
                builtin_mesh("blob").ok()?,
                [205, 165, 125],
                [25.0, 35.0, -10.0],
            )
        }],
        _ if bare == "teapot" || bare.starts_with("teapot:") => {
            let mesh = builtin_mesh(bare).ok()?;
            vec![ObjectDesc {
                // The teapot's patches bound the body, lid, handle and spout,
                // turned outwards; its inside shows through the gap between
                // lid and body and through the spout. (The coarsest
                // tessellation folds two patches onto one edge.)
                bounds_solids: mesh_openings(&mesh).is_ok(),
                ..object(
                    &format!("builtin:{bare}"),
                    mesh,
                    [220, 170, 120],
                    [0.0, 30.0, 0.0],
                )
            }]
        }
        _ if bare == "overdraw" || bare.starts_with("overdraw:") => {
            let params: Vec<&str> = bare.split(':').skip(1).collect();
            toward_eye = [0.1, 0.2, 1.0];
            overdraw::overdraw_objects(&params)?
        }
        _ => {
            let synthetic = synthetic::synthetic_scene(bare)?;
            toward_eye = synthetic.toward_eye;
            synthetic.objects
        }
    };
    let aspect = width.max(1) as f32 / height.max(1) as f32;
    let camera = frame_objects(&objects, toward_eye, 40.0, aspect, 0.75);
    Some(SceneDesc {
        width,
        height,
        background: [16, 18, 28],
        camera,
        light: Some(BUILTIN_LIGHT),
        objects,
    })
}

/// An object at the origin with unit scale and default shading.
pub(crate) fn object(
    mesh_name: &str,
    mesh: MeshData,
    color: [u8; 3],
    rotation_deg: [f32; 3],
) -> ObjectDesc {
    ObjectDesc {
        mesh_name: mesh_name.to_string(),
        mesh,
        color,
        position: [0.0; 3],
        rotation_deg,
        scale: 1.0,
        // The teapot is open (no lid seal, the spout is a hole), so its
        // inside can be seen; closed meshes override this.
        cull_backfaces: false,
        bounds_solids: false,
        shading: None,
    }
}

/// Four spheres in a tight cluster, every pair interpenetrating, laid out
/// as a diamond on screen: one on each side, a large one behind and above,
/// a smaller one in front and below. Each sphere shows part of its
/// intersection curve with every other one.
fn spheres_objects() -> Vec<ObjectDesc> {
    let sphere = shapes::icosphere(DEFAULT_SPHERE_LEVEL);
    let specs: [([f32; 3], f32, [u8; 3]); 4] = [
        ([-0.5, 0.0, 0.0], 0.6, [215, 75, 65]),
        ([0.5, 0.05, 0.0], 0.55, [85, 185, 100]),
        ([0.0, 0.45, -0.5], 0.7, [80, 120, 220]),
        ([0.05, -0.4, 0.45], 0.6, [230, 200, 80]),
    ];
    specs
        .iter()
        .map(|&(position, scale, color)| ObjectDesc {
            position,
            scale,
            // Spheres are closed: their back halves are hidden anyway.
            cull_backfaces: true,
            ..object(
                &format!("builtin:sphere:{DEFAULT_SPHERE_LEVEL}"),
                sphere.clone(),
                color,
                [0.0; 3],
            )
        })
        .collect()
}

/// An object's vertices in world space (scale, rotate X then Y then Z,
/// translate), as the renderer places them.
fn world_positions(object: &ObjectDesc) -> impl Iterator<Item = V3> + '_ {
    let rotation = Mat3::euler_xyz(object.rotation_deg);
    object
        .mesh
        .positions
        .iter()
        .map(move |&p| add(rotation.apply(mul(p, object.scale)), object.position))
}

/// A camera looking at `objects` from direction `toward_eye` (from the
/// objects to the eye, need not be unit length), far enough that their
/// projection spans `fill` of the image in its tighter dimension.
fn frame_objects(
    objects: &[ObjectDesc],
    toward_eye: V3,
    fov_y_deg: f32,
    aspect: f32,
    fill: f32,
) -> CameraDesc {
    let up = [0.0, 1.0, 0.0];
    let near = 0.5;
    let points: Vec<V3> = objects.iter().flat_map(world_positions).collect();
    let back = normalize(toward_eye).unwrap_or([0.0, 0.0, 1.0]);
    let forward = mul(back, -1.0);
    let right = normalize(cross(forward, up)).unwrap_or([1.0, 0.0, 0.0]);
    let true_up = cross(right, forward);
    let tan_y = (fov_y_deg.to_radians() * 0.5).tan() * fill;
    let tan_x = tan_y * aspect;

    // Start from the middle of the bounding box, then recenter on the
    // middle of the projected extent.
    let mut lo = [f32::MAX; 3];
    let mut hi = [f32::MIN; 3];
    for p in &points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let mut target = if points.is_empty() {
        [0.0; 3]
    } else {
        mul(add(lo, hi), 0.5)
    };
    let mut distance = 4.0;
    for _ in 0..3 {
        // Smallest distance at which every point projects inside the
        // `fill` rectangle: |x| <= tan_x * depth, |y| <= tan_y * depth, with
        // depth = distance + q . forward.
        distance = points
            .iter()
            .map(|&p| {
                let q = sub(p, target);
                let along = dot(q, forward);
                let need_x = dot(q, right).abs() / tan_x - along;
                let need_y = dot(q, true_up).abs() / tan_y - along;
                need_x.max(need_y).max(near * 2.0 - along)
            })
            .fold(near * 2.0, f32::max);
        // Where the projected extent's middle lies, moved back onto the
        // target plane.
        let (mut x_lo, mut x_hi, mut y_lo, mut y_hi) = (f32::MAX, f32::MIN, f32::MAX, f32::MIN);
        for &p in &points {
            let q = sub(p, target);
            let depth = distance + dot(q, forward);
            let (x, y) = (dot(q, right) / depth, dot(q, true_up) / depth);
            x_lo = x_lo.min(x);
            x_hi = x_hi.max(x);
            y_lo = y_lo.min(y);
            y_hi = y_hi.max(y);
        }
        if points.is_empty() {
            break;
        }
        let shift_x = (x_lo + x_hi) * 0.5 * distance;
        let shift_y = (y_lo + y_hi) * 0.5 * distance;
        target = add(target, add(mul(right, shift_x), mul(true_up, shift_y)));
    }
    CameraDesc {
        eye: add(target, mul(back, distance)),
        target,
        up,
        fov_y_deg,
        near,
        far: 20.0,
    }
}

#[cfg(test)]
mod tests {
    use super::geom::{length, tri_normal};
    use super::*;

    fn check_basic(mesh: &MeshData) {
        assert_eq!(mesh.positions.len(), mesh.normals.len());
        assert!(!mesh.triangles.is_empty());
        for n in &mesh.normals {
            assert!(n.iter().all(|c| c.is_finite()), "normal {n:?}");
            assert!((length(*n) - 1.0).abs() < 1e-4, "normal {n:?} not unit");
        }
        for p in &mesh.positions {
            assert!(p.iter().all(|c| c.is_finite()), "position {p:?}");
        }
        let count = mesh.positions.len() as u32;
        for t in &mesh.triangles {
            assert!(t.iter().all(|&i| i < count), "triangle {t:?} out of range");
        }
    }

    /// Fraction of triangles whose geometric normal agrees with the sum of
    /// their vertex normals.
    fn winding_agreement(mesh: &MeshData) -> f64 {
        let good = mesh
            .triangles
            .iter()
            .filter(|t| {
                let [a, b, c] = t.map(|i| i as usize);
                let geometric = tri_normal(mesh.positions[a], mesh.positions[b], mesh.positions[c]);
                let smooth = add(add(mesh.normals[a], mesh.normals[b]), mesh.normals[c]);
                dot(geometric, smooth) > 0.0
            })
            .count();
        good as f64 / mesh.triangles.len() as f64
    }

    fn max_radius(mesh: &MeshData) -> f32 {
        mesh.positions
            .iter()
            .map(|&p| length(p))
            .fold(0.0, f32::max)
    }

    #[test]
    fn teapot_data_is_the_classic_set() {
        assert_eq!(teapot_data::PATCHES.len(), 32);
        assert_eq!(teapot_data::POINTS.len(), 306);
        for patch in &teapot_data::PATCHES {
            assert!(patch.iter().all(|&i| (i as usize) < 306));
        }
        // Every point has its mirror image across the classic y = 0 plane.
        for p in &teapot_data::POINTS {
            let mirrored = [p[0], -p[1], p[2]];
            assert!(
                teapot_data::POINTS
                    .iter()
                    .any(|q| (0..3).all(|k| (q[k] - mirrored[k]).abs() < 1e-6)),
                "{p:?} has no mirror image"
            );
        }
        // A few well-known points: rim start, widest body ring, spout tip,
        // knob top and the bottom center.
        assert_eq!(teapot_data::POINTS[0], [1.4, 0.0, 2.4]);
        assert_eq!(teapot_data::POINTS[52], [2.0, 0.0, 1.35]);
        assert_eq!(teapot_data::POINTS[188], [3.525, 0.0, 2.49375]);
        assert_eq!(teapot_data::POINTS[203], [0.0, 0.0, 3.15]);
        assert_eq!(teapot_data::POINTS[269], [0.0, 0.0, 0.0]);
    }

    #[test]
    fn teapot_patches_are_all_wound_the_same_way() {
        let signs = teapot::patch_signs();
        assert_eq!(signs.len(), 32);
        // The classic data is consistently oriented: one sign for all.
        assert!(signs.iter().all(|&s| s == signs[0]), "{signs:?}");
    }

    #[test]
    fn teapot_mesh() {
        let mesh = builtin_mesh("teapot").unwrap();
        assert_eq!(mesh.triangles.len(), 4096);
        assert_eq!(mesh, builtin_mesh("teapot:8").unwrap());
        check_basic(&mesh);
        let agree = winding_agreement(&mesh);
        assert!(agree > 0.95, "winding agreement {agree}");
        assert!(max_radius(&mesh) <= 1.0);
        for n in [1, 2, 3, 5, 16] {
            let m = builtin_mesh(&format!("teapot:{n}")).unwrap();
            assert_eq!(m.triangles.len() as u32, 32 * n * n * 2);
            check_basic(&m);
        }
    }

    #[test]
    fn teapot_faces_outward() {
        let mesh = builtin_mesh("teapot:8").unwrap();
        // Lid on +Y, spout towards +X, handle towards -X.
        let (top, _) = extreme(&mesh, [0.0, 1.0, 0.0]);
        let (spout, _) = extreme(&mesh, [1.0, 0.0, 0.0]);
        let (handle, _) = extreme(&mesh, [-1.0, 0.0, 0.0]);
        assert!(
            mesh.normals[top][1] > 0.9,
            "top normal {:?}",
            mesh.normals[top]
        );
        assert!(spout != handle);
        let bottom_y = mesh.positions.iter().map(|p| p[1]).fold(f32::MAX, f32::min);
        let top_y = mesh.positions[top][1];
        // Body: vertices at mid height and away from the spout and handle
        // have normals pointing away from the vertical axis.
        let axis_x = {
            let pts: Vec<&V3> = mesh
                .positions
                .iter()
                .filter(|p| (p[1] - bottom_y).abs() < 1e-4)
                .collect();
            pts.iter().map(|p| p[0]).sum::<f32>() / pts.len() as f32
        };
        let mid = bottom_y + 0.3 * (top_y - bottom_y);
        let mut checked = 0;
        for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
            let radial = [p[0] - axis_x, 0.0, p[2]];
            if (p[1] - mid).abs() < 0.05 && p[2].abs() > 0.4 {
                assert!(dot(radial, *n) > 0.0, "body normal {n:?} at {p:?}");
                checked += 1;
            }
        }
        assert!(checked > 10);
        // Bottom: normals point down.
        for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
            if (p[1] - bottom_y).abs() < 1e-4 && (p[0] - axis_x).hypot(p[2]) < 0.2 {
                assert!(n[1] < -0.9, "bottom normal {n:?} at {p:?}");
            }
        }
    }

    /// The vertex furthest along `dir` and its distance.
    fn extreme(mesh: &MeshData, dir: V3) -> (usize, f32) {
        mesh.positions
            .iter()
            .enumerate()
            .map(|(i, &p)| (i, dot(p, dir)))
            .fold((0, f32::MIN), |a, b| if b.1 > a.1 { b } else { a })
    }

    #[test]
    fn sphere_meshes() {
        assert_eq!(builtin_mesh("sphere").unwrap().triangles.len(), 1280);
        for level in 1..=4u32 {
            let mesh = builtin_mesh(&format!("sphere:{level}")).unwrap();
            assert_eq!(mesh.triangles.len(), 20 * 4usize.pow(level));
            check_basic(&mesh);
            for p in &mesh.positions {
                assert!((length(*p) - 1.0).abs() < 1e-5);
            }
            for t in &mesh.triangles {
                let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
                assert!(dot(tri_normal(a, b, c), add(add(a, b), c)) > 0.0);
            }
            assert_eq!(winding_agreement(&mesh), 1.0);
        }
    }

    #[test]
    fn starfighter_mesh() {
        let mesh = builtin_mesh("starfighter").unwrap();
        let count = mesh.triangles.len();
        assert!((1000..=3000).contains(&count), "{count} triangles");
        check_basic(&mesh);
        assert!(max_radius(&mesh) <= 1.6);
        // Flat faces and cylinder sides: every triangle agrees with its
        // vertex normals.
        assert_eq!(winding_agreement(&mesh), 1.0);
        // Nose towards -Z.
        let (_, front) = extreme(&mesh, [0.0, 0.0, -1.0]);
        let (_, back) = extreme(&mesh, [0.0, 0.0, 1.0]);
        assert!(front > back);
    }

    #[test]
    fn cube_mesh() {
        let mesh = builtin_mesh("cube").unwrap();
        assert_eq!(mesh.triangles.len(), 12);
        assert_eq!(mesh.positions.len(), 24);
        check_basic(&mesh);
        for t in &mesh.triangles {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
            let n = tri_normal(a, b, c);
            assert!(dot(n, add(add(a, b), c)) > 0.0);
            assert!(dot(n, mesh.normals[t[0] as usize]) > 0.0);
        }
        for p in &mesh.positions {
            assert!(p.iter().all(|c| c.abs() == 1.0));
        }
    }

    #[test]
    fn mesh_name_errors() {
        let err = builtin_mesh("dodecahedron").unwrap_err();
        assert!(
            err.contains("unknown built-in mesh 'dodecahedron'"),
            "{err}"
        );
        for name in BUILTIN_MESHES {
            assert!(err.contains(name), "{err}");
        }
        for bad in [
            "teapot:0",
            "teapot:65",
            "teapot:x",
            "teapot:",
            "sphere:0",
            "sphere:9",
            "cube:2",
            "blob:2",
        ] {
            assert!(builtin_mesh(bad).is_err(), "{bad}");
        }
        assert!(builtin_mesh("teapot:64").is_ok());
        assert!(builtin_mesh("builtin:cube").is_ok());
    }

    #[test]
    fn scenes() {
        for name in BUILTIN_SCENES {
            let scene = builtin_scene(name, 320, 240).unwrap();
            assert_eq!((scene.width, scene.height), (320, 240));
            assert!(!scene.objects.is_empty());
            assert!(scene.light.is_some());
            for object in &scene.objects {
                assert!(object.mesh_name.starts_with("builtin:"));
                check_basic(&object.mesh);
            }
            check_framing(&scene);
        }
        let scene = builtin_scene("teapot:4", 100, 100).unwrap();
        assert_eq!(scene.objects[0].mesh.triangles.len(), 32 * 4 * 4 * 2);
        check_framing(&scene);
        check_framing(&builtin_scene("starfighter", 120, 300).unwrap());
        assert!(builtin_scene("teapot:0", 100, 100).is_none());
        assert!(builtin_scene("nothing", 100, 100).is_none());
        assert!(builtin_scene("cube", 100, 100).is_none());
    }

    #[test]
    fn blob_scene() {
        let mesh = builtin_mesh("blob").unwrap();
        assert_eq!(mesh, builtin_mesh("builtin:blob").unwrap());
        assert_eq!(mesh.triangles.len(), 3700);
        check_basic(&mesh);
        assert_eq!(winding_agreement(&mesh), 1.0);
        let scene = builtin_scene("blob", 240, 240).unwrap();
        assert_eq!(scene, builtin_scene("builtin:blob", 240, 240).unwrap());
        let [object] = &scene.objects[..] else {
            panic!("{} objects", scene.objects.len());
        };
        assert_eq!(object.mesh_name, "builtin:blob");
        assert_eq!(object.mesh, mesh);
        assert!(object.cull_backfaces);
        assert_eq!(object.shading, Some(ShadingDesc::Gouraud));
        check_framing(&scene);
        assert!(builtin_scene("blob:2", 100, 100).is_none());
    }

    /// Every vertex is in view, in front of the near plane, and the
    /// objects span most of the image in at least one direction.
    fn check_framing(scene: &SceneDesc) {
        let cam = &scene.camera;
        let forward = normalize(sub(cam.target, cam.eye)).unwrap();
        let right = normalize(cross(forward, cam.up)).unwrap();
        let up = cross(right, forward);
        let tan_y = (cam.fov_y_deg.to_radians() * 0.5).tan();
        let tan_x = tan_y * scene.width as f32 / scene.height as f32;
        let mut span = 0.0f32;
        for object in &scene.objects {
            for p in world_positions(object) {
                let q = sub(p, cam.eye);
                let depth = dot(q, forward);
                assert!(depth > cam.near && depth < cam.far);
                let x = dot(q, right) / (depth * tan_x);
                let y = dot(q, up) / (depth * tan_y);
                assert!(x.abs() <= 0.8 && y.abs() <= 0.8, "({x}, {y}) out of frame");
                span = span.max(x.abs()).max(y.abs());
            }
        }
        assert!(span > 0.65, "objects only span {span}");
    }

    #[test]
    fn spheres_interpenetrate_pairwise() {
        let scene = builtin_scene("spheres", 200, 150).unwrap();
        let spheres = &scene.objects;
        assert!(spheres.len() >= 4);
        for (i, a) in spheres.iter().enumerate() {
            for b in &spheres[i + 1..] {
                let d = length(sub(a.position, b.position));
                assert!(
                    d < a.scale + b.scale,
                    "{:?} and {:?} do not meet",
                    a.position,
                    b.position
                );
                // Neither swallows the other: the intersection is a curve.
                assert!(d > (a.scale - b.scale).abs());
            }
        }
    }
}
