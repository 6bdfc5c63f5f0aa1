//! A scene as Rust source, for firmware build scripts that put it into flash.
//!
//! The generated statics (`POSITIONS_i`, `NORMALS_i`, `TRIANGLES_i`,
//! `OPENINGS_i` where an object has openings, `OBJECTS`, `SCENE`) go through
//! the same float-to-fixed conversion as host-sim, so a firmware renders the
//! bits host-sim renders. The including module must have these
//! names in scope: `Coord` (`mcu_abuffer::fixed_point::Coord`), `I2F14`
//! (`fixed::types::I2F14`), `Rgb888`, and from `mcu_abuffer::scene` `Camera`,
//! `Light`, `Mesh`, `Normal`, `Scene`, `SceneObject`, `Shading`, `Transform`.

use crate::fixed_bits::{coord3_bits, coord_bits, normal_bits, resolve_shading};
use crate::openings::object_openings;
use crate::scene_desc::{SceneDesc, ShadingDesc};
use std::fmt::Write as _;

/// Bytes of flash one vertex takes (a Q16.16 position and a Q2.14 normal).
pub const VERTEX_FLASH_BYTES: usize = 12 + 6;
/// Bytes of flash one triangle takes (three 32-bit indices).
pub const TRIANGLE_FLASH_BYTES: usize = 12;
/// Bytes of flash one entry of a mesh's openings takes (a 32-bit index or
/// the end of a loop).
pub const OPENING_FLASH_BYTES: usize = 4;

/// A scene turned into Rust statics, with its sizes.
#[derive(Clone, Debug)]
pub struct BakedScene {
    /// The statics, to be written to a file and `include!`d.
    pub source: String,
    /// Vertices over all objects.
    pub vertices: usize,
    /// Triangles over all objects.
    pub triangles: usize,
    /// Objects.
    pub objects: usize,
    /// Flash the meshes take.
    pub mesh_bytes: usize,
}

fn coord3(v: [f32; 3]) -> String {
    let b = coord3_bits(v);
    format!(
        "[Coord::from_bits({}), Coord::from_bits({}), Coord::from_bits({})]",
        b[0], b[1], b[2]
    )
}

fn coord(v: f32) -> String {
    format!("Coord::from_bits({})", coord_bits(v))
}

/// The statics of `desc`; `origin` is named in the generated file's first line.
/// The caller checks the scene with `check_convertible` first. An error names
/// an object that says it bounds solids while its mesh does not
/// ([`object_openings`]).
pub fn bake_scene(desc: &SceneDesc, origin: &str) -> Result<BakedScene, String> {
    let mut s = String::new();
    // Writing to a String cannot fail.
    let _ = writeln!(s, "// Generated from {origin}.");
    let mut opening_entries = 0;
    let mut has_openings = Vec::new();
    for (i, o) in desc.objects.iter().enumerate() {
        let m = &o.mesh;
        let _ = writeln!(
            s,
            "static POSITIONS_{i}: [[Coord; 3]; {}] = [",
            m.positions.len()
        );
        for p in &m.positions {
            let _ = writeln!(s, "{},", coord3(*p));
        }
        let _ = writeln!(
            s,
            "];\nstatic NORMALS_{i}: [Normal; {}] = [",
            m.normals.len()
        );
        for n in &m.normals {
            let b = normal_bits(*n);
            let _ = writeln!(
                s,
                "[I2F14::from_bits({}), I2F14::from_bits({}), I2F14::from_bits({})],",
                b[0], b[1], b[2]
            );
        }
        let _ = writeln!(
            s,
            "];\nstatic TRIANGLES_{i}: [[u32; 3]; {}] = [",
            m.triangles.len()
        );
        for t in &m.triangles {
            let _ = writeln!(s, "[{}, {}, {}],", t[0], t[1], t[2]);
        }
        let _ = writeln!(s, "];");
        let openings = object_openings(o, i)?;
        has_openings.push(openings.is_some());
        if let Some(loops) = openings {
            let entries: usize = loops.iter().map(|l| l.len() + 1).sum();
            opening_entries += entries;
            let _ = writeln!(s, "static OPENINGS_{i}: [u32; {entries}] = [");
            for l in &loops {
                for v in l {
                    let _ = write!(s, "{v}, ");
                }
                let _ = writeln!(s, "mcu_abuffer::scene::OPENING_END,");
            }
            let _ = writeln!(s, "];");
        }
    }
    let has_light = desc.light.is_some();
    let _ = writeln!(
        s,
        "/// The scene's objects.\npub static OBJECTS: [SceneObject<'static>; {}] = [",
        desc.objects.len()
    );
    for (i, o) in desc.objects.iter().enumerate() {
        let openings = if has_openings[i] {
            format!("Some(&OPENINGS_{i})")
        } else {
            "None".to_string()
        };
        let shading = match resolve_shading(o.shading, has_light) {
            ShadingDesc::Unlit => "Unlit",
            ShadingDesc::Flat => "Flat",
            ShadingDesc::Gouraud => "Gouraud",
            ShadingDesc::Quadratic => "Quadratic",
            ShadingDesc::Phong => "Phong",
        };
        let _ = writeln!(
            s,
            "SceneObject {{ mesh: Mesh {{ positions: &POSITIONS_{i}, normals: &NORMALS_{i}, triangles: &TRIANGLES_{i}, openings: {openings} }}, \
             color: Rgb888::new({}, {}, {}), transform: Transform {{ position: {}, rotation_deg: {}, scale: {} }}, \
             cull_backfaces: {}, shading: Shading::{shading} }},",
            o.color[0],
            o.color[1],
            o.color[2],
            coord3(o.position),
            coord3(o.rotation_deg),
            coord(o.scale),
            o.cull_backfaces
        );
    }
    let _ = writeln!(s, "];");
    let cam = &desc.camera;
    let light = match &desc.light {
        None => "None".to_string(),
        Some(l) => format!(
            "Some(Light {{ direction: {}, ambient: {}, diffuse: {}, specular: {}, shininess: {} }})",
            coord3(l.direction),
            coord(l.ambient),
            coord(l.diffuse),
            coord(l.specular),
            l.shininess.round().clamp(1.0, 255.0) as u8
        ),
    };
    let _ = writeln!(
        s,
        "/// The scene.\npub static SCENE: Scene<'static> = Scene {{ width: {}, height: {}, background: Rgb888::new({}, {}, {}), \
         camera: Camera {{ eye: {}, target: {}, up: {}, fov_y_deg: {}, near: {}, far: {} }}, light: {light}, objects: &OBJECTS }};",
        desc.width,
        desc.height,
        desc.background[0],
        desc.background[1],
        desc.background[2],
        coord3(cam.eye),
        coord3(cam.target),
        coord3(cam.up),
        coord(cam.fov_y_deg),
        coord(cam.near),
        coord(cam.far),
    );
    let vertices = desc.objects.iter().map(|o| o.mesh.positions.len()).sum();
    let triangles = desc.objects.iter().map(|o| o.mesh.triangles.len()).sum();
    Ok(BakedScene {
        source: s,
        vertices,
        triangles,
        objects: desc.objects.len(),
        mesh_bytes: vertices * VERTEX_FLASH_BYTES
            + triangles * TRIANGLE_FLASH_BYTES
            + opening_entries * OPENING_FLASH_BYTES,
    })
}
