//! Tests of the OBJ and scene file loaders: valid input gives the expected
//! data, and every kind of bad input gives an error that names the file, the
//! line and the problem.

use std::path::{Path, PathBuf};

use abuffer_scenes::obj::{load_obj, parse_obj, LoadError};
use abuffer_scenes::scene_desc::ShadingDesc;
use abuffer_scenes::scene_file::{load_mesh, load_scene_file, parse_scene};

fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data")
}

fn data(name: &str) -> PathBuf {
    data_dir().join(name)
}

fn assert_close(actual: [f32; 3], expected: [f32; 3]) {
    for axis in 0..3 {
        assert!(
            (actual[axis] - expected[axis]).abs() < 1e-6,
            "{actual:?} is not {expected:?}"
        );
    }
}

/// Checks an error's line and that its message contains every piece.
fn assert_error(err: &LoadError, line: Option<usize>, pieces: &[&str]) {
    assert_eq!(err.line, line, "wrong line in: {err}");
    for piece in pieces {
        assert!(
            err.message.contains(piece),
            "message of `{err}` does not contain `{piece}`"
        );
    }
}

fn obj_error(text: &str) -> LoadError {
    parse_obj(text, "test.obj").expect_err("the OBJ text should have been rejected")
}

/// A scene around one object, with extra text in the places named.
fn scene_text(top: &str, camera: &str, object: &str) -> String {
    format!(
        "{top}\n[camera]\neye = [0, 0, 5]\ntarget = [0, 0, 0]\n{camera}\n\
         [[object]]\nmesh = \"square.obj\"\n{object}\n"
    )
}

fn scene_error(text: &str) -> LoadError {
    parse_scene(text, "test.toml", &data_dir()).expect_err("the scene should have been rejected")
}

// ---------------------------------------------------------------------------
// LoadError

#[test]
fn load_error_display() {
    let with_line = LoadError {
        file: "a.obj".into(),
        line: Some(7),
        message: "bad".into(),
    };
    assert_eq!(with_line.to_string(), "a.obj:7: bad");
    let without = LoadError {
        file: "a.obj".into(),
        line: None,
        message: "bad".into(),
    };
    assert_eq!(without.to_string(), "a.obj: bad");
    let _: &dyn std::error::Error = &without;
}

// ---------------------------------------------------------------------------
// OBJ: valid files

#[test]
fn obj_mixed_forms_quads_and_negative_indices() {
    let mesh = load_obj(&data("mixed_forms.obj")).unwrap();
    // Two quads (two triangles each) and one triangle.
    assert_eq!(
        mesh.triangles,
        vec![[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7], [8, 9, 10]]
    );
    assert_eq!(mesh.positions.len(), 11);
    assert_eq!(mesh.normals.len(), 11);
    // Front quad: given normal (0, 0, 2), normalized.
    for n in &mesh.normals[0..4] {
        assert_close(*n, [0.0, 0.0, 1.0]);
    }
    // Back quad: relative indices -1..-4 are vertices 4, 3, 2, 1.
    assert_eq!(
        &mesh.positions[4..8],
        &[
            [0.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 0.0, 0.0]
        ]
    );
    for n in &mesh.normals[4..8] {
        assert_close(*n, [0.0, 0.0, -1.0]);
    }
    // Last triangle (v/vt form, no normals) lies in the y = 0 plane and is
    // counter-clockwise seen from -Y.
    assert_eq!(
        &mesh.positions[8..11],
        &[[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 0.0, 2.0]]
    );
    for n in &mesh.normals[8..11] {
        assert_close(*n, [0.0, -1.0, 0.0]);
    }
}

#[test]
fn obj_computed_normals_of_flat_square_face_plus_z() {
    let mesh = load_obj(&data("square.obj")).unwrap();
    assert_eq!(mesh.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    assert_eq!(mesh.normals.len(), 4);
    for n in &mesh.normals {
        assert_eq!(*n, [0.0, 0.0, 1.0]);
    }
}

#[test]
fn obj_computed_normals_are_area_weighted() {
    // Vertex 1 is shared by a triangle of area 2 facing +Z and one of area
    // 1/2 facing +Y: the cross products are (0, 0, 4) and (0, 1, 0).
    let text = "v 0 0 0\nv 2 0 0\nv 0 2 0\nv 0 0 1\nv 1 0 0\nf 1 2 3\nf 1 4 5\n";
    let mesh = parse_obj(text, "weights.obj").unwrap();
    let len = 17.0f32.sqrt();
    assert_close(mesh.normals[0], [0.0, 1.0 / len, 4.0 / len]);
    assert_close(mesh.normals[1], [0.0, 0.0, 1.0]);
    assert_close(mesh.normals[4], [0.0, 1.0, 0.0]);
}

#[test]
fn obj_shared_corners_are_merged_and_normals_split_vertices() {
    // Position 1 is used with no normal, with normal 1 and with normal 2:
    // three output vertices. Repeats of a pair share one vertex.
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 0 0 1\nvn 1 0 0\n\
                f 1 2 3\nf 2 4 3\nf 1//1 2//1 3//1\nf 1//2 2//2 3//2\n";
    let mesh = parse_obj(text, "split.obj").unwrap();
    assert_eq!(mesh.triangles.len(), 4);
    assert_eq!(mesh.positions.len(), 4 + 3 + 3);
    assert_eq!(mesh.triangles[1], [1, 3, 2]);
}

#[test]
fn obj_degenerate_triangle_is_kept() {
    let mesh = load_obj(&data("degenerate.obj")).unwrap();
    assert_eq!(mesh.triangles, vec![[0, 1, 2]]);
    // No area to take a normal from: the fallback is +Z.
    for n in &mesh.normals {
        assert_eq!(*n, [0.0, 0.0, 1.0]);
    }
}

#[test]
fn obj_tolerates_crlf_comments_trailing_space_and_other_statements() {
    let text = "# header\r\n\r\nmtllib x.mtl\r\no thing\r\ng part\r\ns 1\r\n\
                v 0 0 0 1.0   \r\nv 1 0 0\t\r\nv 0 1 0 # comment\r\nvt 0.5 0.5\r\n\
                usemtl m\r\nl 1 2\r\np 1\r\nf 1/1 2/1 3/1  \r\n";
    let mesh = parse_obj(text, "crlf.obj").unwrap();
    assert_eq!(mesh.triangles, vec![[0, 1, 2]]);
    assert_eq!(mesh.positions[1], [1.0, 0.0, 0.0]);
}

#[test]
fn obj_pentagon_is_fan_triangulated() {
    let text = "v 0 0 0\nv 1 0 0\nv 2 1 0\nv 1 2 0\nv 0 1 0\nf 1 2 3 4 5\n";
    let mesh = parse_obj(text, "pentagon.obj").unwrap();
    assert_eq!(mesh.triangles, vec![[0, 1, 2], [0, 2, 3], [0, 3, 4]]);
}

#[test]
fn load_mesh_reads_obj_relative_to_base_dir() {
    let mesh = load_mesh("square.obj", &data_dir()).unwrap();
    assert_eq!(mesh, load_obj(&data("square.obj")).unwrap());
}

// ---------------------------------------------------------------------------
// OBJ: errors

#[test]
fn obj_missing_file() {
    let path = data("no_such_file.obj");
    let err = load_obj(&path).unwrap_err();
    assert_eq!(err.file, path.display().to_string());
    assert_error(&err, None, &["cannot read"]);
    assert!(err.to_string().contains("no_such_file.obj"), "{err}");
}

#[test]
fn obj_malformed_number_names_line() {
    let path = data("bad_number.obj");
    let err = load_obj(&path).unwrap_err();
    assert_eq!(err.file, path.display().to_string());
    assert_error(&err, Some(3), &["abc", "invalid number"]);
    assert!(err.to_string().contains("bad_number.obj:3:"), "{err}");
}

#[test]
fn obj_wrong_component_counts() {
    let err = obj_error("v 0 0 0\nv 1 2\n");
    assert_error(&err, Some(2), &["'v'", "3 or 4", "found 2"]);
    let err = obj_error("v 0 0 0 1 5\n");
    assert_error(&err, Some(1), &["'v'", "found 5"]);
    let err = obj_error("v 0 0 0\nvn 0 1\n");
    assert_error(&err, Some(2), &["'vn'", "3 numbers", "found 2"]);
}

#[test]
fn obj_non_finite_coordinates() {
    let err = obj_error("v 0 0 0\nv nan 0 0\n");
    assert_error(&err, Some(2), &["non-finite coordinate", "nan"]);
    let err = obj_error("v 0 inf 0\n");
    assert_error(&err, Some(1), &["non-finite coordinate", "inf"]);
    let err = obj_error("v 0 0 0\nvn 0 -inf 0\n");
    assert_error(&err, Some(2), &["non-finite coordinate"]);
    // Too large for f32 turns into infinity.
    let err = obj_error("v 0 0 1e39\n");
    assert_error(&err, Some(1), &["non-finite coordinate"]);
}

#[test]
fn obj_zero_length_normal() {
    let err = obj_error("v 0 0 0\nvn 0 0 0\n");
    assert_error(&err, Some(2), &["zero-length normal"]);
}

#[test]
fn obj_face_index_out_of_range() {
    let err = obj_error("v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 7\n");
    assert_error(
        &err,
        Some(5),
        &["vertex index 7", "out of range", "3 vertices"],
    );
    // Only the vertices defined so far count.
    let err = obj_error("v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n");
    assert_error(&err, Some(3), &["vertex index 3", "2 vertices"]);
    let err = obj_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n");
    assert_error(&err, Some(4), &["vertex index -4", "out of range"]);
    let err = obj_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//2\n");
    assert_error(
        &err,
        Some(5),
        &["normal index 2", "out of range", "1 normal"],
    );
}

#[test]
fn obj_face_index_zero() {
    let err = obj_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
    assert_error(&err, Some(4), &["index 0"]);
    let err = obj_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//0 2//1 3//1\n");
    assert_error(&err, Some(5), &["normal index 0"]);
}

#[test]
fn obj_malformed_index_tokens() {
    for token in ["1//", "a/b", "1/", "x", "1/2/3/4", "2.5"] {
        let text = format!("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf {token} 2 3\n");
        let err = obj_error(&text);
        assert_error(&err, Some(6), &["malformed face vertex", token]);
    }
}

#[test]
fn obj_face_with_too_few_vertices() {
    let err = obj_error("v 0 0 0\nv 1 0 0\nf 1 2\n");
    assert_error(&err, Some(3), &["face has 2 vertices", "at least 3"]);
    let err = obj_error("v 0 0 0\nf\n");
    assert_error(&err, Some(2), &["face has 0 vertices"]);
}

#[test]
fn obj_empty_mesh() {
    let path = data("no_faces.obj");
    let err = load_obj(&path).unwrap_err();
    assert_eq!(err.file, path.display().to_string());
    assert_error(&err, None, &["empty mesh: no faces"]);
    let err = obj_error("");
    assert_error(&err, None, &["empty mesh"]);
}

// ---------------------------------------------------------------------------
// Scene files: valid files

#[test]
fn scene_full_file_loads_every_value() {
    let scene = load_scene_file(&data("full_scene.toml")).unwrap();
    assert_eq!((scene.width, scene.height), (320, 200));
    assert_eq!(scene.background, [16, 16, 32]);

    let camera = &scene.camera;
    assert_eq!(camera.eye, [0.0, 0.5, 4.0]);
    assert_eq!(camera.target, [0.0, 0.0, 0.0]);
    assert_eq!(camera.up, [0.0, 1.0, 0.0]);
    assert_eq!(camera.fov_y_deg, 50.0);
    assert_eq!(camera.near, 0.25);
    assert_eq!(camera.far, 30.0);

    let light = scene.light.as_ref().expect("the scene has a light");
    assert_eq!(light.direction, [0.3, 0.6, 1.0]);
    assert_eq!(light.ambient, 0.2);
    assert_eq!(light.diffuse, 0.7);
    assert_eq!(light.specular, 0.5);
    assert_eq!(light.shininess, 32.0);

    assert_eq!(scene.objects.len(), 3);
    let first = &scene.objects[0];
    assert_eq!(first.mesh_name, "square.obj");
    assert_eq!(first.mesh, load_obj(&data("square.obj")).unwrap());
    assert_eq!(first.color, [220, 180, 140]);
    assert_eq!(first.position, [1.0, -0.5, 0.25]);
    assert_eq!(first.rotation_deg, [10.0, 30.0, -5.0]);
    assert_eq!(first.scale, 1.5);
    assert!(first.cull_backfaces);
    assert_eq!(first.shading, Some(ShadingDesc::Flat));

    let second = &scene.objects[1];
    assert_eq!(second.mesh_name, "mixed_forms.obj");
    assert_eq!(second.mesh.triangles.len(), 5);
    assert_eq!(second.shading, Some(ShadingDesc::Unlit));
    assert!(second.bounds_solids && !first.bounds_solids);

    let third = &scene.objects[2];
    assert_eq!(third.mesh, first.mesh);
    assert_eq!(third.shading, Some(ShadingDesc::Gouraud));
}

#[test]
fn scene_defaults_are_applied() {
    let scene = load_scene_file(&data("minimal_scene.toml")).unwrap();
    assert_eq!((scene.width, scene.height), (240, 240));
    assert_eq!(scene.background, [0, 0, 0]);
    assert_eq!(scene.camera.eye, [0.0, 0.0, 5.0]);
    assert_eq!(scene.camera.up, [0.0, 1.0, 0.0]);
    assert_eq!(scene.camera.fov_y_deg, 40.0);
    assert_eq!(scene.camera.near, 0.5);
    assert_eq!(scene.camera.far, 20.0);
    assert!(scene.light.is_none());
    assert_eq!(scene.objects.len(), 1);
    let object = &scene.objects[0];
    assert_eq!(object.color, [200, 200, 200]);
    assert_eq!(object.position, [0.0; 3]);
    assert_eq!(object.rotation_deg, [0.0; 3]);
    assert_eq!(object.scale, 1.0);
    assert!(!object.cull_backfaces);
    assert!(!object.bounds_solids);
    assert_eq!(object.shading, None);
}

#[test]
fn scene_light_defaults_are_applied() {
    let text = scene_text("", "[light]\ndirection = [0, 0, 1]", "");
    let scene = parse_scene(&text, "test.toml", &data_dir()).unwrap();
    let light = scene.light.unwrap();
    assert_eq!(light.direction, [0.0, 0.0, 1.0]);
    assert_eq!(
        (
            light.ambient,
            light.diffuse,
            light.specular,
            light.shininess
        ),
        (0.15, 0.75, 0.4, 24.0)
    );
}

// ---------------------------------------------------------------------------
// Scene files: errors

#[test]
fn scene_missing_file() {
    let path = data("no_such_scene.toml");
    let err = load_scene_file(&path).unwrap_err();
    assert_eq!(err.file, path.display().to_string());
    assert_error(&err, None, &["cannot read"]);
}

#[test]
fn scene_unknown_key_at_top_level() {
    let err = scene_error(&scene_text("widht = 100", "", ""));
    assert_eq!(err.file, "test.toml");
    assert_error(&err, Some(1), &["unknown field", "widht"]);
}

#[test]
fn scene_unknown_key_in_camera() {
    // Line 1 is empty, then [camera], eye, target, and the extra key.
    let err = scene_error(&scene_text("", "fov = 30", ""));
    assert_error(&err, Some(5), &["unknown field", "`fov`"]);
}

#[test]
fn scene_unknown_key_in_object() {
    let text = scene_text("", "", "color = [1, 2, 3]\nsclae = 2.0");
    let err = scene_error(&text);
    assert_error(&err, Some(9), &["unknown field", "sclae"]);
}

#[test]
fn scene_unknown_key_in_light() {
    let err = scene_error(&scene_text(
        "",
        "[light]\ndirection = [0, 0, 1]\nglow = 1",
        "",
    ));
    assert_error(&err, Some(7), &["unknown field", "glow"]);
}

#[test]
fn scene_syntax_error_names_line() {
    let err = scene_error("width = 10\nheight = = 3\n");
    assert_eq!(err.file, "test.toml");
    assert_eq!(err.line, Some(2), "{err}");
}

#[test]
fn scene_missing_required_parts() {
    let err = scene_error("[[object]]\nmesh = \"square.obj\"\n");
    assert_error(&err, None, &["camera"]);
    let err = scene_error("[camera]\neye = [0, 0, 5]\ntarget = [0, 0, 0]\n");
    assert_error(&err, None, &["no objects"]);
    let err = scene_error("[camera]\neye = [0, 0, 5]\n[[object]]\nmesh = \"square.obj\"\n");
    assert_error(&err, Some(1), &["missing field", "target"]);
}

#[test]
fn scene_shading_names() {
    for (name, shading) in [
        ("unlit", ShadingDesc::Unlit),
        ("flat", ShadingDesc::Flat),
        ("gouraud", ShadingDesc::Gouraud),
        ("quadratic", ShadingDesc::Quadratic),
        ("phong", ShadingDesc::Phong),
    ] {
        let text = scene_text("", "", &format!("shading = \"{name}\""));
        let scene = parse_scene(&text, "test.toml", &data_dir()).unwrap();
        assert_eq!(scene.objects[0].shading, Some(shading), "{name}");
    }
}

#[test]
fn scene_bad_shading_name() {
    let err = scene_error(&scene_text("", "", "shading = \"toon\""));
    assert_error(&err, Some(8), &["toon", "gouraud", "quadratic", "phong"]);
}

#[test]
fn scene_image_size_limits() {
    let err = scene_error(&scene_text("width = 0", "", ""));
    assert_error(&err, Some(1), &["width", "between 1 and 2048"]);
    let err = scene_error(&scene_text("height = 4096", "", ""));
    assert_error(&err, Some(1), &["height", "2048"]);
}

#[test]
fn scene_color_range() {
    let err = scene_error(&scene_text("background = [0, 256, 0]", "", ""));
    assert_error(&err, Some(1), &["background", "256", "0..=255"]);
    let err = scene_error(&scene_text("", "", "color = [-1, 0, 0]"));
    assert_error(&err, Some(8), &["color", "-1", "0..=255"]);
}

#[test]
fn scene_camera_checks() {
    let cases: &[(&str, &[&str])] = &[
        ("near = 0.0", &["near", "greater than 0"]),
        ("near = 30.0", &["far", "greater than near"]),
        ("far = 0.1", &["far", "greater than near"]),
        ("far = 5000.0", &["far", "1000"]),
        ("fov_y_deg = 180.0", &["fov_y_deg", "180"]),
        ("fov_y_deg = 0", &["fov_y_deg"]),
        ("fov_y_deg = nan", &["fov_y_deg", "finite"]),
        ("up = [0.0, 0.0, -2.0]", &["up", "parallel"]),
        ("up = [0.0, 0.0, 0.0]", &["up"]),
        ("target = [0, 0, 5]", &["eye and target"]),
    ];
    for (line, pieces) in cases {
        let text =
            format!("[camera]\neye = [0, 0, 5]\n{line}\n[[object]]\nmesh = \"square.obj\"\n");
        // Give `target` unless the case sets it.
        let text = if line.starts_with("target") {
            text
        } else {
            text.replace("[camera]\n", "[camera]\ntarget = [0, 0, 0]\n")
        };
        let err = scene_error(&text);
        let expected_line = if line.starts_with("target") { 3 } else { 4 };
        assert_error(&err, Some(expected_line), pieces);
    }
    // Looking straight down with the default up vector.
    let err = scene_error(
        "[camera]\neye = [0, 5, 0]\ntarget = [0, 0, 0]\n[[object]]\nmesh = \"square.obj\"\n",
    );
    assert_error(&err, Some(3), &["parallel", "up"]);
    let err = scene_error(&scene_text("", "", "").replace("[0, 0, 5]", "[0, inf, 5]"));
    assert_error(&err, Some(3), &["eye", "finite"]);
}

#[test]
fn scene_light_checks() {
    let cases: &[(&str, &[&str])] = &[
        ("direction = [0, 0, 0]", &["direction", "zero"]),
        (
            "direction = [0, 0, 1]\nshininess = 0.5",
            &["shininess", "1 and 255"],
        ),
        (
            "direction = [0, 0, 1]\nshininess = 300",
            &["shininess", "255"],
        ),
        (
            "direction = [0, 0, 1]\nambient = -0.1",
            &["ambient", "0 and 4"],
        ),
        (
            "direction = [0, 0, 1]\ndiffuse = 5",
            &["diffuse", "0 and 4"],
        ),
        (
            "direction = [0, 0, 1]\nspecular = inf",
            &["specular", "finite"],
        ),
    ];
    for (body, pieces) in cases {
        let text = scene_text("", &format!("[light]\n{body}"), "");
        let err = scene_error(&text);
        let expected_line = 5 + body.lines().count();
        assert_error(&err, Some(expected_line), pieces);
    }
}

#[test]
fn scene_object_checks() {
    let err = scene_error(&scene_text("", "", "scale = 0.0"));
    assert_error(&err, Some(8), &["scale", "greater than 0"]);
    let err = scene_error(&scene_text("", "", "scale = -2"));
    assert_error(&err, Some(8), &["scale"]);
    let err = scene_error(&scene_text("", "", "scale = nan"));
    assert_error(&err, Some(8), &["scale", "finite"]);
    let err = scene_error(&scene_text("", "", "position = [0, 1e39, 0]"));
    assert_error(&err, Some(8), &["position", "finite"]);
    let err = scene_error(&scene_text("", "", "rotation_deg = [0, 0]"));
    assert_error(&err, Some(8), &["length 2"]);
}

#[test]
fn scene_missing_obj_names_obj_and_scene() {
    let scene_path = data("missing_mesh_scene.toml");
    let err = load_scene_file(&scene_path).unwrap_err();
    assert_eq!(err.file, data("does_not_exist.obj").display().to_string());
    assert_error(
        &err,
        None,
        &[
            "cannot read mesh 'does_not_exist.obj'",
            "missing_mesh_scene.toml",
        ],
    );
}

#[test]
fn scene_bad_obj_keeps_obj_name_and_line() {
    let err = load_scene_file(&data("bad_mesh_scene.toml")).unwrap_err();
    assert_eq!(err.file, data("bad_number.obj").display().to_string());
    assert_error(&err, Some(3), &["abc"]);
}

#[test]
fn scene_unknown_builtin_names_scene_line() {
    let text = "[camera]\neye = [0, 0, 5]\ntarget = [0, 0, 0]\n\n[[object]]\n\
                mesh = \"builtin:no_such_builtin_mesh\"\n";
    let err = scene_error(text);
    assert_eq!(err.file, "test.toml");
    assert_error(&err, Some(6), &["no_such_builtin_mesh"]);
    let err = load_mesh("builtin:no_such_builtin_mesh", Path::new(".")).unwrap_err();
    assert!(err.to_string().contains("no_such_builtin_mesh"), "{err}");
}

#[test]
fn load_mesh_reports_obj_errors() {
    let err = load_mesh("bad_number.obj", &data_dir()).unwrap_err();
    assert_error(&err, Some(3), &["abc"]);
}

#[test]
fn scene_and_load_mesh_accept_builtins() {
    let text =
        "[camera]\neye = [0, 0, 5]\ntarget = [0, 0, 0]\n\n[[object]]\nmesh = \"builtin:cube\"\n";
    let scene = parse_scene(text, "test.toml", &data_dir()).unwrap();
    assert_eq!(scene.objects[0].mesh_name, "builtin:cube");
    assert_eq!(scene.objects[0].mesh.triangles.len(), 12);
    let mesh = load_mesh("builtin:cube", Path::new(".")).unwrap();
    assert_eq!(mesh, scene.objects[0].mesh);
}
