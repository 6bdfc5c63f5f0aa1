//! The openings of a mesh: the loops of edges that only one triangle uses.
//!
//! A two-sided object whose mesh bounds solids (every edge shared by two
//! triangles that run it in opposite directions, faces turned outwards) except
//! for some openings shows the faces it turns away only through those
//! openings: a ray from a viewer outside the solids that meets such a face
//! from behind has entered a solid on the way, through a face turned towards
//! it or through an opening. So the renderer may skip every face turned away
//! whose screen box meets no opening's (see `mcu_abuffer::scene::Mesh::openings`).
//!
//! An opening whose closing fan lies inside the solid of another part of the
//! mesh (the teapot's spout where it enters the body) shows nothing: on
//! either side of the fan that part's solid holds the point, so a ray that
//! crosses the fan has entered a solid before, through a face nearer than
//! it. [`object_openings`] leaves such openings out, so the renderer skips
//! the faces turned away behind them too.
//!
//! The loops are found on the fixed-point positions the renderer draws
//! ([`crate::fixed_bits::coord3_bits`]): vertices at the same fixed-point
//! position are one vertex there, and triangles with two corners at one
//! position have no area and are never drawn.

use std::collections::HashMap;

use crate::fixed_bits::coord3_bits;
use crate::scene_desc::{MeshData, ObjectDesc};

/// The openings of object `index` as the renderer takes them: `None` unless
/// the object says it bounds solids and is drawn two-sided (a culled object
/// skips every face turned away anyway). An error names the object when its
/// mesh does not bound solids.
pub fn object_openings(object: &ObjectDesc, index: usize) -> Result<Option<Vec<Vec<u32>>>, String> {
    if !object.bounds_solids || object.cull_backfaces {
        return Ok(None);
    }
    let shape = MeshShape::of(&object.mesh).map_err(|e| {
        format!(
            "object {index} (mesh '{}') says it bounds solids, but {e}",
            object.mesh_name
        )
    })?;
    let buried = shape.buried_loops();
    Ok(Some(
        shape
            .loops_as_vertices()
            .into_iter()
            .zip(buried)
            .filter_map(|(chain, buried)| (!buried).then_some(chain))
            .collect(),
    ))
}

/// The mesh's openings, each a loop of vertex indices in the order its
/// edges run; none for a closed mesh.
///
/// Errors say why the mesh does not bound solids: an edge used twice in the
/// same direction (faces turned inconsistently) or by more than two
/// triangles, a vertex where openings touch, or a part whose faces are turned
/// inwards (its volume, closed over its openings, is not positive).
pub fn mesh_openings(mesh: &MeshData) -> Result<Vec<Vec<u32>>, String> {
    MeshShape::of(mesh).map(|shape| shape.loops_as_vertices())
}

/// A mesh's triangles and openings on its fixed-point positions, checked to
/// bound solids.
struct MeshShape {
    /// One fixed-point position per id.
    points: Vec<[i32; 3]>,
    /// One vertex index of the mesh per id.
    representative: Vec<u32>,
    /// The triangles with area, as ids.
    triangles: Vec<[u32; 3]>,
    /// The openings, as ids in the order their edges run.
    loops: Vec<Vec<u32>>,
}

impl MeshShape {
    fn of(mesh: &MeshData) -> Result<Self, String> {
        // One id per fixed-point position, and one vertex index that has it.
        let mut ids: HashMap<[i32; 3], u32> = HashMap::new();
        let mut representative = Vec::new();
        let mut points = Vec::new();
        let id: Vec<u32> = mesh
            .positions
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let bits = coord3_bits(*p);
                *ids.entry(bits).or_insert_with(|| {
                    representative.push(i as u32);
                    points.push(bits);
                    representative.len() as u32 - 1
                })
            })
            .collect();
        let triangles: Vec<[u32; 3]> = mesh
            .triangles
            .iter()
            .map(|t| t.map(|v| id[v as usize]))
            .filter(|t| t[0] != t[1] && t[1] != t[2] && t[2] != t[0])
            .collect();
        // Directed edges; an edge without its reverse is on an opening.
        let mut edges: HashMap<(u32, u32), u32> = HashMap::new();
        for t in &triangles {
            for k in 0..3 {
                *edges.entry((t[k], t[(k + 1) % 3])).or_default() += 1;
            }
        }
        let mut next: HashMap<u32, u32> = HashMap::new();
        let position = |v: u32| points[v as usize];
        for (&(a, b), &count) in &edges {
            if count > 1 {
                return Err(format!(
                    "the edge from {:?} to {:?} is used by {count} triangles in the same direction \
                     (faces turned inconsistently, or more than two faces on one edge)",
                    position(a),
                    position(b)
                ));
            }
            if !edges.contains_key(&(b, a)) && next.insert(a, b).is_some() {
                return Err(format!(
                    "openings touch at the vertex at {:?} (fixed-point bits)",
                    position(a)
                ));
            }
        }
        // Chain the opening edges into loops, from the smallest vertex id on, so
        // the list does not depend on the hash map's order.
        let mut starts: Vec<u32> = next.keys().copied().collect();
        starts.sort_unstable();
        let mut loops: Vec<Vec<u32>> = Vec::new();
        for start in starts {
            if !next.contains_key(&start) {
                continue;
            }
            let mut chain = vec![start];
            let mut v = start;
            loop {
                match next.remove(&v) {
                    Some(w) if w == start => break,
                    Some(w) => {
                        chain.push(w);
                        v = w;
                    }
                    None => {
                        return Err(format!(
                            "the opening through the vertex at {:?} (fixed-point bits) \
                             does not close",
                            position(v)
                        ))
                    }
                }
            }
            loops.push(chain);
        }
        check_volumes(&triangles, &loops, &points)?;
        Ok(MeshShape {
            points,
            representative,
            triangles,
            loops,
        })
    }

    /// The openings as loops of the mesh's vertex indices.
    fn loops_as_vertices(&self) -> Vec<Vec<u32>> {
        self.loops
            .iter()
            .map(|chain| {
                chain
                    .iter()
                    .map(|&v| self.representative[v as usize])
                    .collect()
            })
            .collect()
    }

    /// For each opening, whether its fan lies inside the solid of another
    /// part of the mesh: then no ray from outside the solids enters one
    /// through it, since on either side of the fan that part's solid holds
    /// the point, and the renderer need not count it. Decided in exact
    /// integer arithmetic; where a test meets a degenerate case (a point on
    /// a plane, a ray along an edge) the opening counts.
    fn buried_loops(&self) -> Vec<bool> {
        let parts = part_of_points(&self.triangles, self.points.len());
        // Each part's closed surface (its triangles and its openings' fans),
        // the parts one after another.
        let mut by_part: Vec<(u32, [u32; 3])> = self
            .triangles
            .iter()
            .copied()
            .chain(self.loops.iter().flat_map(|chain| fan(chain)))
            .map(|t| (parts[t[0] as usize], t))
            .collect();
        by_part.sort_by_key(|(part, _)| *part);
        let corners = |t: [u32; 3]| t.map(|v| self.points[v as usize].map(i128::from));
        let triangles: Vec<[[i128; 3]; 3]> = by_part.iter().map(|(_, t)| corners(*t)).collect();
        let part_surfaces: Vec<(u32, &[[[i128; 3]; 3]])> = by_part
            .chunk_by(|a, b| a.0 == b.0)
            .scan(0, |start, group| {
                let range = *start..*start + group.len();
                *start = range.end;
                Some((group[0].0, &triangles[range]))
            })
            .collect();
        self.loops
            .iter()
            .map(|chain| {
                let own = parts[chain[0] as usize];
                let fan_triangles: Vec<[[i128; 3]; 3]> = fan(chain).map(corners).collect();
                let fan_box = bounds(fan_triangles.iter().flatten());
                let start = self.points[chain[0] as usize].map(i128::from);
                part_surfaces
                    .iter()
                    .filter(|(part, _)| *part != own)
                    .any(|(_, surface)| {
                        let apart = surface.iter().all(|s| {
                            !boxes_meet(s, &fan_box)
                                || fan_triangles.iter().all(|f| !triangles_may_meet(s, f))
                        });
                        apart && winding_number(surface, start).is_some_and(|w| w >= 1)
                    })
            })
            .collect()
    }
}

/// The fan that closes an opening: triangles from its first vertex, running
/// its edges the other way round.
fn fan(chain: &[u32]) -> impl Iterator<Item = [u32; 3]> + '_ {
    chain[1..].windows(2).map(move |w| [chain[0], w[1], w[0]])
}

/// The connected part of each point (a representative point id), over
/// triangles with `points` ids.
fn part_of_points(triangles: &[[u32; 3]], points: usize) -> Vec<u32> {
    let mut parent: Vec<u32> = (0..points as u32).collect();
    fn root(parent: &mut [u32], mut v: u32) -> u32 {
        while parent[v as usize] != v {
            let up = parent[parent[v as usize] as usize];
            parent[v as usize] = up;
            v = up;
        }
        v
    }
    for t in triangles {
        for k in 1..3 {
            let (a, b) = (root(&mut parent, t[0]), root(&mut parent, t[k]));
            parent[a as usize] = b;
        }
    }
    (0..points as u32).map(|v| root(&mut parent, v)).collect()
}

/// The triple product `u . (v x w)`: six times the signed volume of the
/// tetrahedron with edges `u`, `v`, `w` from one corner.
fn triple(u: [i128; 3], v: [i128; 3], w: [i128; 3]) -> i128 {
    u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
        + u[2] * (v[0] * w[1] - v[1] * w[0])
}

/// The sign of the volume of the tetrahedron `a b c d` (positive when `d`
/// lies on the side that `(b - a) x (c - a)` points to).
fn orient(a: [i128; 3], b: [i128; 3], c: [i128; 3], d: [i128; 3]) -> i128 {
    let [u, v, w] = [b, c, d].map(|p| [p[0] - a[0], p[1] - a[1], p[2] - a[2]]);
    triple(u, v, w).signum()
}

/// Whether segment `p q` crosses triangle `t`: `Some(true)` or `Some(false)`,
/// `None` when an end lies on its plane or the segment meets its boundary.
fn segment_crosses(p: [i128; 3], q: [i128; 3], t: &[[i128; 3]; 3]) -> Option<bool> {
    let [a, b, c] = *t;
    let (sp, sq) = (orient(a, b, c, p), orient(a, b, c, q));
    if sp == 0 || sq == 0 {
        return None;
    }
    if sp == sq {
        return Some(false);
    }
    let sides = [orient(p, q, a, b), orient(p, q, b, c), orient(p, q, c, a)];
    if sides.contains(&0) {
        return None;
    }
    Some(sides[0] == sides[1] && sides[1] == sides[2])
}

/// The box of `points`: the least and the largest of each coordinate.
fn bounds<'p>(points: impl Iterator<Item = &'p [i128; 3]>) -> [[i128; 3]; 2] {
    points.fold([[i128::MAX; 3], [i128::MIN; 3]], |[lo, hi], p| {
        [
            core::array::from_fn(|k| lo[k].min(p[k])),
            core::array::from_fn(|k| hi[k].max(p[k])),
        ]
    })
}

/// Whether triangle `t` meets the box `b` (closed boxes).
fn boxes_meet(t: &[[i128; 3]; 3], b: &[[i128; 3]; 2]) -> bool {
    let [lo, hi] = bounds(t.iter());
    (0..3).all(|k| lo[k] <= b[1][k] && b[0][k] <= hi[k])
}

/// Whether two triangles may meet (true also for every degenerate case).
fn triangles_may_meet(s: &[[i128; 3]; 3], t: &[[i128; 3]; 3]) -> bool {
    if !boxes_meet(s, &bounds(t.iter())) {
        return false;
    }
    let edges_cross = |a: &[[i128; 3]; 3], b: &[[i128; 3]; 3]| {
        (0..3).any(|k| segment_crosses(a[k], a[(k + 1) % 3], b) != Some(false))
    };
    edges_cross(s, t) || edges_cross(t, s)
}

/// How many times the closed surface `surface` (triangles turned outwards)
/// winds around `p`: the crossings of a ray from `p`, out minus in. `None`
/// when every ray tried meets a degenerate case.
fn winding_number(surface: &[[[i128; 3]; 3]], p: [i128; 3]) -> Option<i64> {
    // Far enough to leave any Q16.16 mesh: its coordinates are below 2^31.
    const FAR: i128 = 1 << 34;
    let directions = [[FAR, 3, 7], [5, FAR, 11], [13, 17, FAR], [-FAR, 19, -23]];
    directions.iter().find_map(|d| {
        let q = [p[0] + d[0], p[1] + d[1], p[2] + d[2]];
        surface.iter().try_fold(0i64, |w, t| {
            Some(match segment_crosses(p, q, t)? {
                // Leaving through a face turned outwards: `p` behind it.
                true if orient(t[0], t[1], t[2], p) < 0 => w + 1,
                true => w - 1,
                false => w,
            })
        })
    })
}

/// Each connected part, closed over its openings by a fan from each loop's
/// first vertex, must enclose a positive volume (exact, on the fixed-point
/// bits).
fn check_volumes(
    triangles: &[[u32; 3]],
    loops: &[Vec<u32>],
    points: &[[i32; 3]],
) -> Result<(), String> {
    let part = part_of_points(triangles, points.len());
    let det = |t: [u32; 3]| -> i128 {
        let [p, q, r] = t.map(|v| points[v as usize].map(i128::from));
        triple(p, q, r)
    };
    let mut volumes: HashMap<u32, i128> = HashMap::new();
    for t in triangles {
        *volumes.entry(part[t[0] as usize]).or_default() += det(*t);
    }
    // The loop runs its edges the way the faces beside it do; the fan that
    // closes it runs them the other way, as a closed surface would.
    for chain in loops {
        for t in fan(chain) {
            *volumes.entry(part[chain[0] as usize]).or_default() += det(t);
        }
    }
    let mut parts: Vec<(u32, i128)> = volumes.into_iter().collect();
    parts.sort_unstable();
    match parts.iter().find(|(_, v)| *v <= 0) {
        Some((v, _)) => Err(format!(
            "the part through the vertex at {:?} has its faces turned inwards \
             (its volume, closed over its openings, is not positive)",
            points[*v as usize]
        )),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::builtins::builtin_mesh;

    #[test]
    fn a_closed_mesh_has_no_openings() {
        for name in ["cube", "sphere", "blob"] {
            assert_eq!(
                mesh_openings(&builtin_mesh(name).unwrap()),
                Ok(vec![]),
                "{name}"
            );
        }
    }

    #[test]
    fn a_cube_without_a_face_has_one_opening_of_four_vertices() {
        let mut cube = builtin_mesh("cube").unwrap();
        cube.triangles.truncate(10);
        let loops = mesh_openings(&cube).unwrap();
        assert_eq!(loops.len(), 1);
        assert_eq!(loops[0].len(), 4);
    }

    #[test]
    fn the_teapot_has_six_openings() {
        // The lid's and the body's rims, and both ends of the handle and of
        // the spout (the bottom's seams close in fixed point).
        let loops = mesh_openings(&builtin_mesh("teapot").unwrap()).unwrap();
        let sizes: Vec<usize> = loops.iter().map(|l| l.len()).collect();
        assert_eq!(sizes, [32, 16, 16, 16, 16, 32]);
        // The coarsest tessellation folds two of the handle's patches onto
        // one edge; the others bound solids.
        let coarsest = mesh_openings(&builtin_mesh("teapot:1").unwrap()).unwrap_err();
        assert!(coarsest.contains("same direction"), "{coarsest}");
        for n in 2..=16 {
            let name = format!("teapot:{n}");
            assert!(
                mesh_openings(&builtin_mesh(&name).unwrap()).is_ok(),
                "{name}"
            );
        }
    }

    #[test]
    fn the_volume_closed_over_an_opening_does_not_depend_on_where_the_mesh_is() {
        // A closed surface's volume is the same wherever it lies; an open box
        // closed with its fan too, wherever it lies, and turned inside out it
        // is refused wherever it lies.
        for shift in [
            [0.0, 0.0, 0.0],
            [50.0, -20.0, -300.0],
            [0.0, -300.0, 10.0],
            [0.0, 300.0, 0.0],
        ] {
            let mut open_box = builtin_mesh("cube").unwrap();
            open_box.triangles.truncate(10);
            for p in &mut open_box.positions {
                for k in 0..3 {
                    p[k] += shift[k];
                }
            }
            assert!(mesh_openings(&open_box).is_ok(), "{shift:?}");
            for t in &mut open_box.triangles {
                t.swap(1, 2);
            }
            assert!(mesh_openings(&open_box).is_err(), "{shift:?}");
        }
    }

    #[test]
    fn faces_turned_inwards_or_inconsistently_are_refused() {
        let mut cube = builtin_mesh("cube").unwrap();
        for t in &mut cube.triangles {
            t.swap(1, 2);
        }
        let err = mesh_openings(&cube).unwrap_err();
        assert!(err.contains("turned inwards"), "{err}");
        let mut cube = builtin_mesh("cube").unwrap();
        cube.triangles[0].swap(1, 2);
        let err = mesh_openings(&cube).unwrap_err();
        assert!(err.contains("same direction"), "{err}");
    }

    /// A closed cube of half-size `big` around the origin and, shifted by
    /// `shift` along x, a unit cube without two of its triangles (one
    /// opening).
    fn open_box_and_cube(big: f32, shift: f32) -> MeshData {
        let cube = builtin_mesh("cube").unwrap();
        let mut mesh = cube.clone();
        for p in &mut mesh.positions {
            *p = p.map(|c| c * big);
        }
        let base = mesh.positions.len() as u32;
        mesh.positions
            .extend(cube.positions.iter().map(|p| [p[0] + shift, p[1], p[2]]));
        mesh.normals.extend(cube.normals.iter());
        mesh.triangles
            .extend(cube.triangles[..10].iter().map(|t| t.map(|v| v + base)));
        mesh
    }

    #[test]
    fn an_opening_inside_another_part_is_buried() {
        let buried = |mesh: &MeshData| MeshShape::of(mesh).unwrap().buried_loops();
        let mut open_box = builtin_mesh("cube").unwrap();
        open_box.triangles.truncate(10);
        assert_eq!(buried(&open_box), [false]);
        // Inside the large cube, beside it, and through its face at x = 3.
        assert_eq!(buried(&open_box_and_cube(3.0, 0.0)), [true]);
        assert_eq!(buried(&open_box_and_cube(3.0, 10.0)), [false]);
        assert_eq!(buried(&open_box_and_cube(3.0, 2.5)), [false]);
        // The teapot: the spout's end within the body. The handle shares
        // vertices with the body (one part), and a part is not tested
        // against itself, so the handle's ends count; the rims and the
        // spout's tip are open.
        let teapot = builtin_mesh("teapot").unwrap();
        assert_eq!(buried(&teapot), [false, false, false, true, false, false]);
        // The renderer is given the others.
        let object = ObjectDesc {
            bounds_solids: true,
            ..crate::builtins::object("test", open_box_and_cube(3.0, 0.0), [255; 3], [0.0; 3])
        };
        assert_eq!(object_openings(&object, 0), Ok(Some(vec![])));
    }
}
