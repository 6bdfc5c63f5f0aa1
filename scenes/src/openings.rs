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
    mesh_openings(&object.mesh).map(Some).map_err(|e| {
        format!(
            "object {index} (mesh '{}') says it bounds solids, but {e}",
            object.mesh_name
        )
    })
}

/// The mesh's openings, each a loop of vertex indices in the order its
/// edges run; none for a closed mesh.
///
/// Errors say why the mesh does not bound solids: an edge used twice in the
/// same direction (faces turned inconsistently) or by more than two
/// triangles, a vertex where openings touch, or a part whose faces are turned
/// inwards (its volume, closed over its openings, is not positive).
pub fn mesh_openings(mesh: &MeshData) -> Result<Vec<Vec<u32>>, String> {
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
                        "the opening through the vertex at {:?} (fixed-point bits) does not close",
                        position(v)
                    ))
                }
            }
        }
        loops.push(chain);
    }
    check_volumes(&triangles, &loops, &points)?;
    Ok(loops
        .iter()
        .map(|chain| chain.iter().map(|&v| representative[v as usize]).collect())
        .collect())
}

/// Each connected part, closed over its openings by a fan from each loop's
/// first vertex, must enclose a positive volume (exact, on the fixed-point
/// bits).
fn check_volumes(
    triangles: &[[u32; 3]],
    loops: &[Vec<u32>],
    points: &[[i32; 3]],
) -> Result<(), String> {
    let mut parent: Vec<u32> = (0..points.len() as u32).collect();
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
    let det = |t: [u32; 3]| -> i128 {
        let [p, q, r] = t.map(|v| points[v as usize].map(i128::from));
        p[0] * (q[1] * r[2] - q[2] * r[1]) - p[1] * (q[0] * r[2] - q[2] * r[0])
            + p[2] * (q[0] * r[1] - q[1] * r[0])
    };
    let mut volumes: HashMap<u32, i128> = HashMap::new();
    for t in triangles {
        *volumes.entry(root(&mut parent, t[0])).or_default() += det(*t);
    }
    // The loop runs its edges the way the faces beside it do; the fan that
    // closes it runs them the other way, as a closed surface would.
    for chain in loops {
        let part = root(&mut parent, chain[0]);
        for w in chain[1..].windows(2) {
            *volumes.entry(part).or_default() += det([chain[0], w[1], w[0]]);
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
}
