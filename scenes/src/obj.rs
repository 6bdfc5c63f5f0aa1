//! Wavefront OBJ loading.
//!
//! This is a deliberately small parser written for this project instead of a
//! general OBJ crate: what matters here is that every problem in a file is
//! reported with the file name and the line it is on.
//!
//! Supported: `v` (an optional fourth `w` value is read and dropped), `vn`,
//! and `f` with three or more corners in the forms `v`, `v/vt`, `v//vn` and
//! `v/vt/vn`, including negative (relative) indices. Polygons are split into a
//! fan of triangles that keeps the winding of the file. Every other statement
//! (`vt`, `o`, `g`, `s`, `usemtl`, `mtllib`, `l`, `p`, ...) is skipped, as are
//! comments and blank lines.
//!
//! The resulting [`MeshData`] has exactly one normal per vertex: each distinct
//! (position, normal) pair met in the faces becomes one output vertex. Face
//! corners without a normal share a normal computed from the surrounding
//! triangles, weighted by their area.

use std::collections::HashMap;
use std::fmt;
use std::path::Path;

use crate::scene_desc::MeshData;
use crate::wide_vector::{cross, length, sub, widen};

/// An error while loading a scene or mesh file, with where it happened.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadError {
    /// The file at fault, as it was named to the loader.
    pub file: String,
    /// The 1-based line at fault, when the problem is on one line.
    pub line: Option<usize>,
    /// What is wrong.
    pub message: String,
}

impl LoadError {
    /// Makes an error about line `line` (1-based) of `file`.
    pub fn at_line(file: impl Into<String>, line: usize, message: impl Into<String>) -> Self {
        LoadError {
            file: file.into(),
            line: Some(line),
            message: message.into(),
        }
    }

    /// Makes an error about `file` as a whole, with no particular line.
    pub fn in_file(file: impl Into<String>, message: impl Into<String>) -> Self {
        LoadError {
            file: file.into(),
            line: None,
            message: message.into(),
        }
    }
}

impl fmt::Display for LoadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(line) => write!(f, "{}:{}: {}", self.file, line, self.message),
            None => write!(f, "{}: {}", self.file, self.message),
        }
    }
}

impl std::error::Error for LoadError {}

/// Reads and parses the OBJ file at `path`.
///
/// Errors name the file as `path` displays. A file that cannot be read gives
/// an error without a line that includes the operating system's reason.
pub fn load_obj(path: &Path) -> Result<MeshData, LoadError> {
    let file_name = path.display().to_string();
    let bytes = read_regular_file(path)
        .map_err(|e| LoadError::in_file(&file_name, format!("cannot read file: {e}")))?;
    parse_obj_bytes(&bytes, &file_name)
}

/// Reads a whole file, refusing anything but a regular file: a device or a pipe
/// named as a mesh (`/dev/zero`, `/dev/stdin`) would never end or block.
pub(crate) fn read_regular_file(path: &Path) -> std::io::Result<Vec<u8>> {
    if !std::fs::metadata(path)?.is_file() {
        return Err(std::io::Error::other("not a regular file"));
    }
    std::fs::read(path)
}

/// Parses OBJ data that has already been read from a file.
///
/// Checks that the data is UTF-8 first (reporting the line of the first bad
/// byte), then behaves like [`parse_obj`].
pub(crate) fn parse_obj_bytes(bytes: &[u8], file_name: &str) -> Result<MeshData, LoadError> {
    match std::str::from_utf8(bytes) {
        Ok(text) => parse_obj(text, file_name),
        Err(e) => {
            let good = &bytes[..e.valid_up_to()];
            let line = 1 + good.iter().filter(|&&b| b == b'\n').count();
            Err(LoadError::at_line(
                file_name,
                line,
                "the file is not valid UTF-8 text",
            ))
        }
    }
}

/// Parses OBJ text; `file_name` is only used in error messages.
pub fn parse_obj(text: &str, file_name: &str) -> Result<MeshData, LoadError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut parser = Parser::default();
    for (index, raw_line) in text.split('\n').enumerate() {
        parser
            .statement(raw_line)
            .map_err(|message| LoadError::at_line(file_name, index + 1, message))?;
    }
    if parser.triangles.is_empty() {
        return Err(LoadError::in_file(file_name, "empty mesh: no faces"));
    }
    parser
        .build()
        .map_err(|message| LoadError::in_file(file_name, message))
}

/// One corner of a face after its indices have been resolved: 0-based indices
/// into the positions and normals read so far.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
struct Corner {
    position: usize,
    normal: Option<usize>,
}

/// The state of a parse: everything read so far.
#[derive(Default)]
struct Parser {
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    tex_coord_count: usize,
    triangles: Vec<[Corner; 3]>,
    /// Scratch space for the corners of the face being read.
    face: Vec<Corner>,
}

impl Parser {
    /// Handles one line of the file. The error is the message only; the
    /// caller adds the file name and line number.
    fn statement(&mut self, raw_line: &str) -> Result<(), String> {
        let line = match raw_line.find('#') {
            Some(hash) => &raw_line[..hash],
            None => raw_line,
        };
        let mut tokens = line.split_whitespace();
        let Some(keyword) = tokens.next() else {
            return Ok(());
        };
        match keyword {
            "v" => {
                let args: Vec<&str> = tokens.collect();
                if args.len() != 3 && args.len() != 4 {
                    return Err(format!(
                        "'v' needs 3 or 4 numbers (x y z [w]), found {}",
                        args.len()
                    ));
                }
                let position = read_coordinates("v", &args[..3])?;
                if let Some(w) = args.get(3) {
                    // The weight is not used, but it still has to be a number.
                    parse_number("v", w)?;
                }
                self.positions.push(position);
            }
            "vn" => {
                let args: Vec<&str> = tokens.collect();
                if args.len() != 3 {
                    return Err(format!(
                        "'vn' needs 3 numbers (x y z), found {}",
                        args.len()
                    ));
                }
                let n = read_coordinates("vn", &args)?;
                self.normals.push(normalize_given(n)?);
            }
            "vt" => self.tex_coord_count += 1,
            "f" => self.face(tokens)?,
            _ => {}
        }
        Ok(())
    }

    /// Reads the corners of an `f` statement and adds its triangle fan.
    fn face<'a>(&mut self, tokens: impl Iterator<Item = &'a str>) -> Result<(), String> {
        self.face.clear();
        for token in tokens {
            let (v, vt, vn) = split_face_token(token)?;
            let position = resolve_index(v, self.positions.len(), "vertex", "vertices")?;
            if let Some(vt) = vt {
                resolve_index(
                    vt,
                    self.tex_coord_count,
                    "texture coordinate",
                    "texture coordinates",
                )?;
            }
            let normal = match vn {
                Some(vn) => Some(resolve_index(vn, self.normals.len(), "normal", "normals")?),
                None => None,
            };
            self.face.push(Corner { position, normal });
        }
        if self.face.len() < 3 {
            return Err(format!(
                "face has {} {}; at least 3 are needed",
                self.face.len(),
                if self.face.len() == 1 {
                    "vertex"
                } else {
                    "vertices"
                }
            ));
        }
        let first = self.face[0];
        for pair in self.face[1..].windows(2) {
            self.triangles.push([first, pair[0], pair[1]]);
        }
        Ok(())
    }

    /// Turns the faces read into a mesh with one normal per vertex.
    fn build(self) -> Result<MeshData, String> {
        // Area-weighted face normal sums per input position, for corners that
        // come without a normal. Summed in f64 so that large or tiny models
        // neither overflow nor lose the small triangles.
        let mut sums = vec![[0.0f64; 3]; self.positions.len()];
        for triangle in &self.triangles {
            let [a, b, c] = triangle.map(|corner| widen(self.positions[corner.position]));
            let n = cross(sub(b, a), sub(c, a));
            for corner in triangle {
                let sum = &mut sums[corner.position];
                for axis in 0..3 {
                    sum[axis] += n[axis];
                }
            }
        }

        let mut mesh = MeshData::default();
        let mut output_index: HashMap<Corner, u32> = HashMap::new();
        mesh.triangles.reserve(self.triangles.len());
        for triangle in &self.triangles {
            let mut out = [0u32; 3];
            for (slot, corner) in out.iter_mut().zip(triangle) {
                *slot = match output_index.get(corner) {
                    Some(&index) => index,
                    None => {
                        let index = u32::try_from(mesh.positions.len())
                            .map_err(|_| "too many vertices for one mesh".to_string())?;
                        mesh.positions.push(self.positions[corner.position]);
                        mesh.normals.push(match corner.normal {
                            Some(n) => self.normals[n],
                            None => normalize_sum(sums[corner.position]),
                        });
                        output_index.insert(*corner, index);
                        index
                    }
                };
            }
            mesh.triangles.push(out);
        }
        Ok(mesh)
    }
}

/// Parses one number of statement `keyword`.
fn parse_number(keyword: &str, token: &str) -> Result<f32, String> {
    token
        .parse::<f32>()
        .map_err(|_| format!("invalid number '{token}' in '{keyword}' statement"))
}

/// Parses three coordinates, which must be finite.
fn read_coordinates(keyword: &str, args: &[&str]) -> Result<[f32; 3], String> {
    let mut out = [0.0f32; 3];
    for (slot, token) in out.iter_mut().zip(args) {
        let value = parse_number(keyword, token)?;
        if !value.is_finite() {
            return Err(format!(
                "non-finite coordinate '{token}' in '{keyword}' statement"
            ));
        }
        *slot = value;
    }
    Ok(out)
}

/// Normalizes a normal given in the file; a zero-length normal is an error.
fn normalize_given(n: [f32; 3]) -> Result<[f32; 3], String> {
    let wide = widen(n);
    let length = length(wide);
    if length == 0.0 {
        return Err("zero-length normal in 'vn' statement".to_string());
    }
    Ok(wide.map(|c| (c / length) as f32))
}

/// Normalizes a computed normal sum, falling back to +Z when it is zero.
fn normalize_sum(sum: [f64; 3]) -> [f32; 3] {
    let length = length(sum);
    if length > 0.0 && length.is_finite() {
        sum.map(|c| (c / length) as f32)
    } else {
        [0.0, 0.0, 1.0]
    }
}

/// Splits a face corner such as `3`, `3/1`, `3//2` or `3/1/2` into its
/// vertex, texture coordinate and normal indices (still 1-based or negative).
fn split_face_token(token: &str) -> Result<(i64, Option<i64>, Option<i64>), String> {
    let malformed = || {
        format!("malformed face vertex '{token}': expected v, v/vt, v//vn or v/vt/vn with integer indices")
    };
    let parse = |part: &str| part.parse::<i64>().map_err(|_| malformed());
    let parts: Vec<&str> = token.split('/').collect();
    match parts.as_slice() {
        [v] => Ok((parse(v)?, None, None)),
        [v, vt] => Ok((parse(v)?, Some(parse(vt)?), None)),
        [v, vt, vn] => {
            let vt = if vt.is_empty() {
                None
            } else {
                Some(parse(vt)?)
            };
            Ok((parse(v)?, vt, Some(parse(vn)?)))
        }
        _ => Err(malformed()),
    }
}

/// Turns a 1-based or negative OBJ index into a 0-based index, given how many
/// elements of that kind have been defined so far.
fn resolve_index(index: i64, defined: usize, what: &str, plural: &str) -> Result<usize, String> {
    if index == 0 {
        return Err(format!(
            "{what} index 0 is invalid: OBJ indices start at 1 (or count back from -1)"
        ));
    }
    let count = i64::try_from(defined).unwrap_or(i64::MAX);
    let resolved = if index > 0 { index - 1 } else { count + index };
    if resolved < 0 || resolved >= count {
        return Err(format!(
            "{what} index {index} is out of range: {defined} {} defined so far",
            if defined == 1 { what } else { plural }
        ));
    }
    Ok(resolved as usize)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fan_keeps_winding() {
        let mesh = parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n", "t.obj").unwrap();
        assert_eq!(mesh.triangles, vec![[0, 1, 2], [0, 2, 3]]);
        for n in &mesh.normals {
            assert_eq!(*n, [0.0, 0.0, 1.0]);
        }
    }

    #[test]
    fn token_forms() {
        assert_eq!(split_face_token("3"), Ok((3, None, None)));
        assert_eq!(split_face_token("3/1"), Ok((3, Some(1), None)));
        assert_eq!(split_face_token("3//2"), Ok((3, None, Some(2))));
        assert_eq!(split_face_token("-3/1/-2"), Ok((-3, Some(1), Some(-2))));
        for bad in ["1//", "a/b", "1/", "/1", "1/2/3/4", "", "1.5"] {
            assert!(split_face_token(bad).is_err(), "{bad:?} accepted");
        }
    }

    #[test]
    fn relative_indices() {
        assert_eq!(resolve_index(-1, 4, "vertex", "vertices"), Ok(3));
        assert_eq!(resolve_index(-4, 4, "vertex", "vertices"), Ok(0));
        assert!(resolve_index(-5, 4, "vertex", "vertices").is_err());
        assert!(resolve_index(5, 4, "vertex", "vertices").is_err());
    }
}
