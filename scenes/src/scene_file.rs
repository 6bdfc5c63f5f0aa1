//! Scene files (TOML).
//!
//! A scene file describes the image size, the background, a camera, an
//! optional directional light and one or more objects:
//!
//! ```toml
//! width = 240                      # optional, default 240
//! height = 240                     # optional, default 240
//! background = [16, 16, 32]        # optional, default [0, 0, 0]
//!
//! [camera]
//! eye = [0.0, 0.5, 4.0]
//! target = [0.0, 0.0, 0.0]
//! up = [0.0, 1.0, 0.0]             # optional, default [0, 1, 0]
//! fov_y_deg = 40.0                 # optional, default 40
//! near = 0.5                       # optional, default 0.5
//! far = 20.0                       # optional, default 20
//!
//! [light]                          # optional; without it all objects are unlit
//! direction = [0.3, 0.6, 1.0]
//! ambient = 0.15                   # optional, default 0.15
//! diffuse = 0.75                   # optional, default 0.75
//! specular = 0.4                   # optional, default 0.4
//! shininess = 24.0                 # optional, default 24
//!
//! [[object]]
//! mesh = "model.obj"               # relative to the scene file, or "builtin:NAME"
//! color = [220, 180, 140]          # optional, default [200, 200, 200]
//! position = [0.0, 0.0, 0.0]       # optional, default [0, 0, 0]
//! rotation_deg = [0.0, 30.0, 0.0]  # optional; about X, then Y, then Z
//! scale = 1.0                      # optional, default 1
//! cull_backfaces = false           # optional, default false
//! bounds_solids = false            # optional, default false; see below
//! shading = "quadratic"            # optional: "unlit", "flat", "gouraud", "quadratic" or "phong"
//! ```
//!
//! `bounds_solids = true` says that the mesh bounds solids with its faces
//! turned outwards, closed but for openings (a teapot whose lid does not
//! seal, a cup): a two-sided object (`cull_backfaces = false`) then skips the
//! faces it turns away that no opening can show, which is most of them, and
//! draws the same image faster. The mesh is checked when the scene is
//! converted (every edge shared by two triangles running it in opposite
//! directions, but the openings'; each part enclosing a positive volume), and
//! a mesh that fails is an error that names the object. A mesh that passes
//! the check but passes through itself can still break the promise; leave
//! the key out for such meshes.
//!
//! Unknown keys are errors, and every value is checked; errors carry the
//! scene file's name and, where it can be found, the line at fault.

use std::collections::HashMap;
use std::ops::Range;
use std::path::Path;

use serde::Deserialize;
use toml::Spanned;

use crate::obj::{self, LoadError};
use crate::scene_desc::{CameraDesc, LightDesc, MeshData, ObjectDesc, SceneDesc, ShadingDesc};
use crate::wide_vector::{cross, length, sub, widen};

/// The prefix that selects a built-in mesh instead of an OBJ file.
const BUILTIN_PREFIX: &str = "builtin:";

/// Largest accepted image width or height, in pixels.
const MAX_IMAGE_SIDE: i64 = 2048;

/// Largest accepted far plane distance (a limit of the renderer).
const MAX_FAR: f64 = 1000.0;

/// Reads and parses the scene file at `path`, loading the meshes it names.
///
/// OBJ paths in the file are relative to the directory that holds it.
pub fn load_scene_file(path: &Path) -> Result<SceneDesc, LoadError> {
    let file_name = path.display().to_string();
    let text = std::fs::read_to_string(path)
        .map_err(|e| LoadError::in_file(&file_name, format!("cannot read scene file: {e}")))?;
    let base_dir = path.parent().unwrap_or_else(|| Path::new(""));
    parse_scene(&text, &file_name, base_dir)
}

/// Parses scene file text and loads the meshes it names.
///
/// `file_name` is used in error messages; OBJ paths in the scene are resolved
/// against `base_dir`.
pub fn parse_scene(text: &str, file_name: &str, base_dir: &Path) -> Result<SceneDesc, LoadError> {
    let source = Source { text, file_name };
    let raw: RawScene = toml::from_str(text).map_err(|e| source.toml_error(&e))?;
    let mut meshes = MeshCache::default();
    build_scene(&source, raw, base_dir, &mut meshes)
}

/// Loads a mesh given as an OBJ path (relative to `base_dir`) or as
/// `builtin:NAME`.
///
/// Errors about an OBJ file name the file by its path joined to `base_dir`;
/// errors about a built-in mesh name it as the `spec` given.
pub fn load_mesh(spec: &str, base_dir: &Path) -> Result<MeshData, LoadError> {
    match spec.strip_prefix(BUILTIN_PREFIX) {
        Some(name) => crate::builtins::builtin_mesh(name).map_err(|m| LoadError::in_file(spec, m)),
        None => obj::load_obj(&base_dir.join(spec)),
    }
}

// ---------------------------------------------------------------------------
// The file as serde sees it. Values that are checked later are wrapped in
// `Spanned` so that an error can point at their line.

#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a scene table")]
struct RawScene {
    width: Option<Spanned<i64>>,
    height: Option<Spanned<i64>>,
    background: Option<Spanned<[i64; 3]>>,
    camera: Spanned<RawCamera>,
    light: Option<Spanned<RawLight>>,
    #[serde(default)]
    object: Vec<Spanned<RawObject>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a [camera] table")]
struct RawCamera {
    eye: Spanned<[f64; 3]>,
    target: Spanned<[f64; 3]>,
    up: Option<Spanned<[f64; 3]>>,
    fov_y_deg: Option<Spanned<f64>>,
    near: Option<Spanned<f64>>,
    far: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a [light] table")]
struct RawLight {
    direction: Spanned<[f64; 3]>,
    ambient: Option<Spanned<f64>>,
    diffuse: Option<Spanned<f64>>,
    specular: Option<Spanned<f64>>,
    shininess: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "an [[object]] table")]
struct RawObject {
    mesh: Spanned<String>,
    color: Option<Spanned<[i64; 3]>>,
    position: Option<Spanned<[f64; 3]>>,
    rotation_deg: Option<Spanned<[f64; 3]>>,
    scale: Option<Spanned<f64>>,
    cull_backfaces: Option<bool>,
    bounds_solids: Option<bool>,
    shading: Option<RawShading>,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "lowercase")]
enum RawShading {
    Unlit,
    Flat,
    Gouraud,
    Quadratic,
    Phong,
}

impl From<RawShading> for ShadingDesc {
    fn from(shading: RawShading) -> Self {
        match shading {
            RawShading::Unlit => ShadingDesc::Unlit,
            RawShading::Flat => ShadingDesc::Flat,
            RawShading::Gouraud => ShadingDesc::Gouraud,
            RawShading::Quadratic => ShadingDesc::Quadratic,
            RawShading::Phong => ShadingDesc::Phong,
        }
    }
}

// ---------------------------------------------------------------------------
// Checking and conversion.

/// The scene text and its name, to turn byte spans into located errors.
struct Source<'a> {
    text: &'a str,
    file_name: &'a str,
}

impl Source<'_> {
    /// The 1-based line holding byte `offset`.
    fn line_of(&self, offset: usize) -> usize {
        let end = offset.min(self.text.len());
        1 + self.text.as_bytes()[..end]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
    }

    /// An error about the value at `span`.
    fn error(&self, span: Range<usize>, message: impl Into<String>) -> LoadError {
        LoadError::at_line(self.file_name, self.line_of(span.start), message)
    }

    /// An error about the file as a whole.
    fn file_error(&self, message: impl Into<String>) -> LoadError {
        LoadError::in_file(self.file_name, message)
    }

    /// Converts a TOML syntax or type error.
    fn toml_error(&self, e: &toml::de::Error) -> LoadError {
        // Some messages span several lines ("invalid table header\nexpected
        // ..."): keep them on one.
        let message = e
            .message()
            .lines()
            .map(str::trim)
            .filter(|l| !l.is_empty())
            .collect::<Vec<_>>()
            .join(": ");
        // The toml crate gives some errors (a key with no value at the end of
        // the file) no message at all.
        let message = if message.is_empty() {
            "invalid TOML: a value is missing or incomplete".to_string()
        } else {
            message
        };
        // The only required top-level key; toml gives no useful span for it.
        if message == "missing field `camera`" {
            return self.file_error("missing [camera] table");
        }
        match e.span() {
            Some(span) => self.error(span, message),
            None => self.file_error(message),
        }
    }
}

/// Meshes already loaded for this scene, so that an OBJ file used by several
/// objects is read once.
#[derive(Default)]
struct MeshCache {
    loaded: HashMap<String, MeshData>,
}

fn build_scene(
    src: &Source<'_>,
    raw: RawScene,
    base_dir: &Path,
    meshes: &mut MeshCache,
) -> Result<SceneDesc, LoadError> {
    let width = image_side(src, "width", raw.width)?;
    let height = image_side(src, "height", raw.height)?;
    let background = match raw.background {
        Some(bg) => color(src, "background", &bg)?,
        None => [0, 0, 0],
    };
    let camera = camera(src, raw.camera)?;
    let light = raw.light.map(|l| light(src, l)).transpose()?;
    if raw.object.is_empty() {
        return Err(src.file_error(
            "the scene has no objects: add at least one [[object]] table with a mesh",
        ));
    }
    let objects = raw
        .object
        .into_iter()
        .map(|o| object(src, o.into_inner(), base_dir, meshes))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(SceneDesc {
        width,
        height,
        background,
        camera,
        light,
        objects,
    })
}

fn image_side(src: &Source<'_>, key: &str, value: Option<Spanned<i64>>) -> Result<u32, LoadError> {
    let Some(value) = value else {
        return Ok(240);
    };
    let v = *value.get_ref();
    if !(1..=MAX_IMAGE_SIDE).contains(&v) {
        return Err(src.error(
            value.span(),
            format!("{key} = {v} is out of range: it must be between 1 and {MAX_IMAGE_SIDE}"),
        ));
    }
    Ok(v as u32)
}

fn color(src: &Source<'_>, key: &str, value: &Spanned<[i64; 3]>) -> Result<[u8; 3], LoadError> {
    let mut out = [0u8; 3];
    for (slot, &c) in out.iter_mut().zip(value.get_ref()) {
        *slot = u8::try_from(c).map_err(|_| {
            src.error(
                value.span(),
                format!("{key} component {c} is out of range: 8-bit colors use 0..=255"),
            )
        })?;
    }
    Ok(out)
}

/// Converts a float to `f32`, requiring it to be finite (also after the
/// conversion, which turns very large values into infinity).
fn finite(src: &Source<'_>, key: &str, value: &Spanned<f64>) -> Result<f32, LoadError> {
    let v = *value.get_ref() as f32;
    if !v.is_finite() {
        return Err(src.error(
            value.span(),
            format!(
                "{key} = {} is not a finite number in the f32 range",
                value.get_ref()
            ),
        ));
    }
    Ok(v)
}

/// Like [`finite`] for a vector of three floats.
fn finite3(src: &Source<'_>, key: &str, value: &Spanned<[f64; 3]>) -> Result<[f32; 3], LoadError> {
    let mut out = [0.0f32; 3];
    for (slot, &c) in out.iter_mut().zip(value.get_ref()) {
        *slot = c as f32;
        if !slot.is_finite() {
            return Err(src.error(
                value.span(),
                format!("{key} has a component that is not a finite number in the f32 range ({c})"),
            ));
        }
    }
    Ok(out)
}

/// An optional float with a default, checked to be finite.
fn finite_or(
    src: &Source<'_>,
    key: &str,
    value: &Option<Spanned<f64>>,
    default: f32,
) -> Result<f32, LoadError> {
    value.as_ref().map_or(Ok(default), |v| finite(src, key, v))
}

fn camera(src: &Source<'_>, raw: Spanned<RawCamera>) -> Result<CameraDesc, LoadError> {
    let camera_span = raw.span();
    let raw = raw.into_inner();
    let eye = finite3(src, "camera eye", &raw.eye)?;
    let target = finite3(src, "camera target", &raw.target)?;
    let up = match &raw.up {
        Some(up) => finite3(src, "camera up", up)?,
        None => [0.0, 1.0, 0.0],
    };
    let fov_y_deg = finite_or(src, "camera fov_y_deg", &raw.fov_y_deg, 40.0)?;
    let near = finite_or(src, "camera near", &raw.near, 0.5)?;
    let far = finite_or(src, "camera far", &raw.far, 20.0)?;

    // Where to point when a check involves a value that may be defaulted.
    let span_or = |value: Option<Range<usize>>| value.unwrap_or_else(|| camera_span.clone());

    if !(fov_y_deg > 0.0 && fov_y_deg < 180.0) {
        return Err(src.error(
            span_or(raw.fov_y_deg.as_ref().map(Spanned::span)),
            format!("camera fov_y_deg = {fov_y_deg} must be greater than 0 and less than 180"),
        ));
    }
    if near <= 0.0 {
        return Err(src.error(
            span_or(raw.near.as_ref().map(Spanned::span)),
            format!("camera near = {near} must be greater than 0"),
        ));
    }
    let far_or_near = raw.far.as_ref().or(raw.near.as_ref()).map(Spanned::span);
    if far <= near {
        return Err(src.error(
            span_or(far_or_near),
            format!("camera far = {far} must be greater than near = {near}"),
        ));
    }
    if f64::from(far) > MAX_FAR {
        return Err(src.error(
            span_or(raw.far.as_ref().map(Spanned::span)),
            format!("camera far = {far} is too large: the renderer allows at most {MAX_FAR}"),
        ));
    }
    if eye == target {
        return Err(src.error(
            raw.target.span(),
            "camera eye and target are the same point, so there is no view direction",
        ));
    }
    let view = sub(widen(target), widen(eye));
    let up_wide = widen(up);
    let side = cross(view, up_wide);
    if length(side) <= 1e-6 * length(view) * length(up_wide) {
        let message = if raw.up.is_some() {
            "camera up must not be zero or parallel to the view direction (target - eye)"
        } else {
            "the view direction (target - eye) is vertical, parallel to the default up \
             [0, 1, 0]: give the camera another up vector"
        };
        return Err(src.error(
            span_or(
                raw.up
                    .as_ref()
                    .map(Spanned::span)
                    .or(Some(raw.target.span())),
            ),
            message,
        ));
    }
    Ok(CameraDesc {
        eye,
        target,
        up,
        fov_y_deg,
        near,
        far,
    })
}

fn light(src: &Source<'_>, raw: Spanned<RawLight>) -> Result<LightDesc, LoadError> {
    let raw = raw.into_inner();
    let direction = finite3(src, "light direction", &raw.direction)?;
    if direction == [0.0, 0.0, 0.0] {
        return Err(src.error(
            raw.direction.span(),
            "light direction must not be the zero vector",
        ));
    }
    let coefficient = |key: &str, value: &Option<Spanned<f64>>, default: f32| {
        let v = finite_or(src, key, value, default)?;
        match value {
            Some(spanned) if !(0.0..=4.0).contains(&v) => Err(src.error(
                spanned.span(),
                format!("{key} = {v} is out of range: it must be between 0 and 4"),
            )),
            _ => Ok(v),
        }
    };
    let ambient = coefficient("light ambient", &raw.ambient, 0.15)?;
    let diffuse = coefficient("light diffuse", &raw.diffuse, 0.75)?;
    let specular = coefficient("light specular", &raw.specular, 0.4)?;
    let shininess = finite_or(src, "light shininess", &raw.shininess, 24.0)?;
    if let Some(spanned) = &raw.shininess {
        if !(1.0..=255.0).contains(&shininess) {
            return Err(src.error(
                spanned.span(),
                format!(
                    "light shininess = {shininess} is out of range: it must be between 1 and 255"
                ),
            ));
        }
    }
    Ok(LightDesc {
        direction,
        ambient,
        diffuse,
        specular,
        shininess,
    })
}

fn object(
    src: &Source<'_>,
    raw: RawObject,
    base_dir: &Path,
    meshes: &mut MeshCache,
) -> Result<ObjectDesc, LoadError> {
    let color = match &raw.color {
        Some(c) => color(src, "object color", c)?,
        None => [200, 200, 200],
    };
    let position = match &raw.position {
        Some(p) => finite3(src, "object position", p)?,
        None => [0.0; 3],
    };
    let rotation_deg = match &raw.rotation_deg {
        Some(r) => finite3(src, "object rotation_deg", r)?,
        None => [0.0; 3],
    };
    let scale = match &raw.scale {
        Some(s) => {
            let v = finite(src, "object scale", s)?;
            if v <= 0.0 {
                return Err(src.error(
                    s.span(),
                    format!("object scale = {v} must be greater than 0"),
                ));
            }
            v
        }
        None => 1.0,
    };
    let mesh = meshes.get(src, &raw.mesh, base_dir)?;
    Ok(ObjectDesc {
        mesh_name: raw.mesh.get_ref().clone(),
        mesh,
        color,
        position,
        rotation_deg,
        scale,
        cull_backfaces: raw.cull_backfaces.unwrap_or(false),
        bounds_solids: raw.bounds_solids.unwrap_or(false),
        shading: raw.shading.map(ShadingDesc::from),
    })
}

impl MeshCache {
    /// Loads the mesh named by an object's `mesh` key, or returns a copy of
    /// the one already loaded.
    fn get(
        &mut self,
        src: &Source<'_>,
        spec: &Spanned<String>,
        base_dir: &Path,
    ) -> Result<MeshData, LoadError> {
        let name = spec.get_ref();
        if let Some(mesh) = self.loaded.get(name) {
            return Ok(mesh.clone());
        }
        let mesh = if let Some(builtin) = name.strip_prefix(BUILTIN_PREFIX) {
            crate::builtins::builtin_mesh(builtin)
                .map_err(|m| src.error(spec.span(), format!("mesh '{name}': {m}")))?
        } else {
            load_referenced_obj(src, spec, &base_dir.join(name))?
        };
        self.loaded.insert(name.clone(), mesh.clone());
        Ok(mesh)
    }
}

/// Reads an OBJ file named in the scene. A file that cannot be read is
/// reported under the OBJ path, saying which scene line referenced it; errors
/// inside the OBJ file keep that file's own name and line.
fn load_referenced_obj(
    src: &Source<'_>,
    spec: &Spanned<String>,
    path: &Path,
) -> Result<MeshData, LoadError> {
    let obj_name = path.display().to_string();
    let bytes = obj::read_regular_file(path).map_err(|e| {
        LoadError::in_file(
            &obj_name,
            format!(
                "cannot read mesh '{}' referenced by {}:{}: {e}",
                spec.get_ref(),
                src.file_name,
                src.line_of(spec.span().start)
            ),
        )
    })?;
    obj::parse_obj_bytes(&bytes, &obj_name)
}
