//! Scene format v1 (docs/scene-format.md), checked rule by rule through the
//! public API: `kdray::scene::parse_scene` and `kdray::scene::load_scene`.
//!
//! Every error test checks the file, the exact line and the exact key of the
//! error, that it prints on one line as `file:line: key: message`, and that
//! the message says what is wrong; rules that do not depend on the format are
//! checked in TOML and in JSON. Most documents are built once with [`Doc`]
//! and rendered both ways, one key per line, so that the expected line of
//! each key is known exactly.

mod common;

use common::TempDir;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::DVec3;
use kdray::scene::obj::load_obj;
use kdray::scene::{
    load_scene, parse_scene, Camera, Light, Material, RenderSettings, Scene, SceneError,
    SceneFormat, ShadowMode, Sphere, Triangle,
};

// ============================================================== temp files

/// A fresh folder under the system temp dir, removed again on drop.
/// Copies the shipped torus.obj and torus.mtl into `folder` of `dir`; returns the OBJ's path.
fn copy_torus(dir: &TempDir, folder: &str) -> PathBuf {
    for name in ["torus.obj", "torus.mtl"] {
        let text = std::fs::read_to_string(models_dir().join(name)).unwrap();
        dir.write(&format!("{folder}/{name}"), &text);
    }
    dir.join(&format!("{folder}/torus.obj"))
}

fn models_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/models")
}

/// A one-triangle OBJ: (0,0,0), (1,0,0), (0,1,0).
const ONE_TRIANGLE_OBJ: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

// ============================================================== parsing and errors

/// The (never read) paths that in-memory documents are parsed as.
const TOML_FILE: &str = "scenes/test.toml";
const JSON_FILE: &str = "scenes/test.json";

fn file_of(format: SceneFormat) -> &'static Path {
    Path::new(match format {
        SceneFormat::Toml => TOML_FILE,
        SceneFormat::Json => JSON_FILE,
    })
}

#[track_caller]
fn parse_ok(text: &str, format: SceneFormat) -> Scene {
    parse_scene(text, file_of(format), format)
        .unwrap_or_else(|e| panic!("expected {format:?} to parse, got: {e}\n---\n{text}"))
}

#[track_caller]
fn parse_err(text: &str, format: SceneFormat) -> SceneError {
    match parse_scene(text, file_of(format), format) {
        Ok(_) => panic!("expected {format:?} to be rejected\n---\n{text}"),
        Err(e) => e,
    }
}

#[track_caller]
fn load_ok(path: &Path) -> Scene {
    load_scene(path).unwrap_or_else(|e| panic!("expected {} to load, got: {e}", path.display()))
}

#[track_caller]
fn load_err(path: &Path) -> SceneError {
    match load_scene(path) {
        Ok(_) => panic!("expected {} to be rejected", path.display()),
        Err(e) => e,
    }
}

/// Checks all the contract promises about an error: the file, the exact line
/// and key, a Display of one line that reads `file:line: key: message`, and
/// a message that mentions each of `words` (case-insensitive).
#[track_caller]
fn assert_error(
    e: &SceneError,
    file: &Path,
    line: Option<usize>,
    key: Option<&str>,
    words: &[&str],
) {
    let shown = e.to_string();
    assert_eq!(e.file, file, "file of `{shown}`");
    assert_eq!(e.line, line, "line of `{shown}`");
    assert_eq!(e.key.as_deref(), key, "key of `{shown}`");
    assert!(
        !shown.contains(['\n', '\r']),
        "the error is not one line: {shown:?}"
    );
    let mut expected = file.display().to_string();
    if let Some(line) = line {
        expected.push_str(&format!(":{line}"));
    }
    if let Some(key) = key {
        expected.push_str(&format!(": {key}"));
    }
    expected.push_str(&format!(": {}", e.message));
    assert_eq!(shown, expected, "Display is not `file:line: key: message`");
    assert!(
        e.message.trim().len() >= 8,
        "the message says too little: `{shown}`"
    );
    let message = e.message.to_lowercase();
    for word in words {
        assert!(
            message.contains(&word.to_lowercase()),
            "the message of `{shown}` should mention {word:?}"
        );
    }
}

#[track_caller]
fn assert_close(got: DVec3, want: DVec3) {
    assert!(
        (got - want).abs().max_element() < 1e-12,
        "got {got}, want {want}"
    );
}

// ============================================================== documents in both formats

/// A scene document written once and rendered as TOML or as JSON, one key per
/// line. Values are written in the syntax the two formats share: numbers,
/// `"strings"` and `[arrays]`.
#[derive(Clone, Default)]
struct Doc(Table);

#[derive(Clone, Default)]
struct Table(Vec<(String, Node)>);

#[derive(Clone)]
enum Node {
    Value(String),
    Table(Table),
    /// An array of tables: `[[name]]` in TOML.
    Array(Vec<Table>),
}

/// `spheres[2]` -> ("spheres", Some(2)); `camera` -> ("camera", None).
fn split_index(segment: &str) -> (&str, Option<usize>) {
    match segment.strip_suffix(']').and_then(|s| s.split_once('[')) {
        Some((name, index)) => (name, Some(index.parse().unwrap())),
        None => (segment, None),
    }
}

fn join(prefix: &str, key: &str) -> String {
    if prefix.is_empty() {
        key.to_string()
    } else {
        format!("{prefix}.{key}")
    }
}

impl Table {
    fn get_mut(&mut self, name: &str) -> Option<&mut Node> {
        self.0.iter_mut().find(|(k, _)| k == name).map(|(_, n)| n)
    }

    /// The table at `segment` (`name` or `name[i]`), made if missing.
    fn child(&mut self, segment: &str) -> &mut Table {
        let (name, index) = split_index(segment);
        if self.get_mut(name).is_none() {
            let node = match index {
                Some(_) => Node::Array(Vec::new()),
                None => Node::Table(Table::default()),
            };
            self.0.push((name.to_string(), node));
        }
        match (self.get_mut(name).unwrap(), index) {
            (Node::Table(t), None) => t,
            (Node::Array(items), Some(i)) => {
                while items.len() <= i {
                    items.push(Table::default());
                }
                &mut items[i]
            }
            _ => panic!("{segment} is not a table here"),
        }
    }
}

impl Doc {
    /// Sets the key at `path` (`camera.vfov`, `spheres[1].radius`,
    /// `materials.red.diffuse`) to `value`, replacing whatever was there.
    fn set(mut self, path: &str, value: &str) -> Self {
        let (parents, last) = match path.rsplit_once('.') {
            Some((parents, last)) => (Some(parents), last),
            None => (None, path),
        };
        let mut table = &mut self.0;
        for segment in parents.into_iter().flat_map(|p| p.split('.')) {
            table = table.child(segment);
        }
        let node = Node::Value(value.to_string());
        match table.get_mut(last) {
            Some(old) => *old = node,
            None => table.0.push((last.to_string(), node)),
        }
        self
    }

    /// Removes the key at `path`.
    fn remove(mut self, path: &str) -> Self {
        let (parents, last) = match path.rsplit_once('.') {
            Some((parents, last)) => (Some(parents), last),
            None => (None, path),
        };
        let mut table = &mut self.0;
        for segment in parents.into_iter().flat_map(|p| p.split('.')) {
            table = table.child(segment);
        }
        table.0.retain(|(k, _)| k != last);
        self
    }

    fn toml(&self) -> Text {
        let mut w = Writer::new(SceneFormat::Toml);
        toml_table(&mut w, "", "", &self.0);
        w.finish()
    }

    fn json(&self) -> Text {
        let mut w = Writer::new(SceneFormat::Json);
        w.plain("{".into());
        json_members(&mut w, "", &self.0, 1);
        w.plain("}".into());
        w.finish()
    }

    fn both(&self) -> [Text; 2] {
        [self.toml(), self.json()]
    }
}

/// A rendered [`Doc`], with the line of every key path.
struct Text {
    text: String,
    format: SceneFormat,
    /// The line of each key (of the header for TOML tables).
    lines: HashMap<String, usize>,
    /// JSON only: the line of each table's closing brace.
    ends: HashMap<String, usize>,
}

impl Text {
    fn file(&self) -> &'static Path {
        file_of(self.format)
    }

    /// The line where `path` is written; for an element of an array value
    /// (`camera.position[1]`) the line of the array.
    #[track_caller]
    fn line(&self, path: &str) -> usize {
        let mut p = path;
        loop {
            if let Some(&line) = self.lines.get(p) {
                return line;
            }
            match p.strip_suffix(']').and_then(|s| s.rsplit_once('[')) {
                Some((shorter, _)) => p = shorter,
                None => panic!("{path} is not in the document:\n{}", self.text),
            }
        }
    }

    /// The line an error about a whole table (a missing key) points at: the
    /// TOML header, or the JSON closing brace (where serde_json notices).
    #[track_caller]
    fn table_line(&self, path: &str) -> usize {
        match self.format {
            SceneFormat::Toml => self.line(path),
            SceneFormat::Json => self.ends[path],
        }
    }

    #[track_caller]
    fn parse_ok(&self) -> Scene {
        parse_ok(&self.text, self.format)
    }

    #[track_caller]
    fn parse_err(&self) -> SceneError {
        parse_err(&self.text, self.format)
    }
}

struct Writer {
    out: Vec<String>,
    format: SceneFormat,
    lines: HashMap<String, usize>,
    ends: HashMap<String, usize>,
}

impl Writer {
    fn new(format: SceneFormat) -> Self {
        Writer {
            out: Vec::new(),
            format,
            lines: HashMap::new(),
            ends: HashMap::new(),
        }
    }

    /// Writes a line that holds `path` (the first such line counts).
    fn line(&mut self, path: &str, text: String) {
        self.out.push(text);
        let n = self.out.len();
        self.lines.entry(path.to_string()).or_insert(n);
    }

    fn plain(&mut self, text: String) {
        self.out.push(text);
    }

    /// An empty line between TOML tables (not at the top).
    fn blank(&mut self) {
        if !self.out.is_empty() {
            self.out.push(String::new());
        }
    }

    /// Ends `path`'s table with `text` (a JSON closing brace).
    fn end(&mut self, path: &str, text: String) {
        self.out.push(text);
        self.ends.insert(path.to_string(), self.out.len());
    }

    fn comma(&mut self) {
        self.out.last_mut().unwrap().push(',');
    }

    fn finish(self) -> Text {
        Text {
            text: self.out.join("\n") + "\n",
            format: self.format,
            lines: self.lines,
            ends: self.ends,
        }
    }
}

/// A table's plain keys, then its sub-tables as `[header]` and its arrays of
/// tables as `[[header]]` (TOML wants a table's own keys before any header).
fn toml_table(w: &mut Writer, header: &str, path: &str, table: &Table) {
    for (key, node) in &table.0 {
        if let Node::Value(value) = node {
            w.line(&join(path, key), format!("{key} = {value}"));
        }
    }
    for (key, node) in &table.0 {
        let (header, path) = (join(header, key), join(path, key));
        match node {
            Node::Value(_) => {}
            Node::Table(sub) => {
                w.blank();
                w.line(&path, format!("[{header}]"));
                toml_table(w, &header, &path, sub);
            }
            Node::Array(items) => {
                for (i, item) in items.iter().enumerate() {
                    let item_path = format!("{path}[{i}]");
                    w.blank();
                    w.line(&path, format!("[[{header}]]"));
                    w.lines.insert(item_path.clone(), w.out.len());
                    toml_table(w, &header, &item_path, item);
                }
            }
        }
    }
}

/// The members of a JSON object, one per line, each table closing on its own line.
fn json_members(w: &mut Writer, path: &str, table: &Table, depth: usize) {
    let pad = "  ".repeat(depth);
    for (i, (key, node)) in table.0.iter().enumerate() {
        if i > 0 {
            w.comma();
        }
        let path = join(path, key);
        match node {
            Node::Value(value) => w.line(&path, format!("{pad}\"{key}\": {value}")),
            Node::Table(sub) => {
                w.line(&path, format!("{pad}\"{key}\": {{"));
                json_members(w, &path, sub, depth + 1);
                w.end(&path, format!("{pad}}}"));
            }
            Node::Array(items) => {
                w.line(&path, format!("{pad}\"{key}\": ["));
                for (j, item) in items.iter().enumerate() {
                    if j > 0 {
                        w.comma();
                    }
                    let item_path = format!("{path}[{j}]");
                    w.line(&item_path, format!("{pad}  {{"));
                    json_members(w, &item_path, item, depth + 2);
                    w.end(&item_path, format!("{pad}  }}"));
                }
                w.plain(format!("{pad}]"));
            }
        }
    }
}

/// A small valid scene: camera, one light, materials red and blue, one
/// sphere and one triangle (so that new entries get index 1).
fn base() -> Doc {
    Doc::default()
        .set("camera.position", "[0, 0, 1]")
        .set("camera.look_at", "[0, 0, 0]")
        .set("lights[0].position", "[5, 5, 5]")
        .set("materials.red.diffuse", "[0.7, 0, 0]")
        .set("materials.blue.diffuse", "[0, 0, 0.7]")
        .set("spheres[0].center", "[0, 0, -1]")
        .set("spheres[0].radius", "0.5")
        .set("spheres[0].material", "\"red\"")
        .set(
            "triangles[0].vertices",
            "[[0, 0, -2], [1, 0, -2], [0, 1, -2]]",
        )
        .set("triangles[0].material", "\"blue\"")
}

/// `base()` plus a second, valid sphere: set one of its keys to test it.
fn two_spheres() -> Doc {
    base()
        .set("spheres[1].center", "[1, 0, -1]")
        .set("spheres[1].radius", "0.25")
        .set("spheres[1].material", "\"blue\"")
}

/// `base()` plus a second, valid triangle.
fn two_triangles() -> Doc {
    base()
        .set(
            "triangles[1].vertices",
            "[[0, 0, -3], [2, 0, -3], [0, 2, -3]]",
        )
        .set("triangles[1].material", "\"red\"")
}

/// `base()` plus a mesh whose OBJ does not exist: fine for every check that
/// comes before the OBJ is read (its keys, material, scale, rotate, translate).
fn with_mesh() -> Doc {
    base()
        .set("meshes[0].path", "\"models/none.obj\"")
        .set("meshes[0].material", "\"red\"")
}

/// Both renderings of `doc` must be rejected with `key`, on the line where
/// that key (or the array holding that element) is written.
#[track_caller]
fn assert_rejected(doc: &Doc, key: &str, words: &[&str]) {
    for text in doc.both() {
        assert_rejected_text(&text, key, words);
    }
}

#[track_caller]
fn assert_rejected_text(text: &Text, key: &str, words: &[&str]) {
    let e = text.parse_err();
    assert_error(&e, text.file(), Some(text.line(key)), Some(key), words);
}

/// Both renderings of `doc` must parse, to the same scene; returns it.
#[track_caller]
fn assert_accepted(doc: &Doc) -> Scene {
    let [toml, json] = doc.both();
    let scene = toml.parse_ok();
    assert_eq!(scene, json.parse_ok(), "TOML and JSON disagree");
    scene
}

#[test]
fn the_doc_helper_writes_what_it_says() {
    let doc = two_spheres();
    let toml = doc.toml();
    assert!(toml.text.starts_with("[camera]\nposition = [0, 0, 1]\n"));
    assert_eq!(toml.line("camera.position"), 2);
    assert_eq!(toml.line("camera.position[2]"), 2);
    assert_eq!(
        toml.text.lines().nth(toml.line("spheres[1]") - 1),
        Some("[[spheres]]")
    );
    let json = doc.json();
    assert_eq!(json.line("camera.position"), 3);
    let radius = json
        .text
        .lines()
        .nth(json.line("spheres[1].radius") - 1)
        .unwrap();
    assert_eq!(radius.trim(), "\"radius\": 0.25,");
    assert_eq!(
        json.text
            .lines()
            .nth(json.ends["spheres[1]"] - 1)
            .unwrap()
            .trim(),
        "}"
    );
    assert_accepted(&doc);
}

// ============================================================== files and syntax

mod files_and_syntax {
    use super::*;

    #[test]
    fn missing_scene_file() {
        let dir = TempDir::new("missing");
        for name in ["nope.toml", "nope.json"] {
            let path = dir.join(name);
            let e = load_err(&path);
            assert_error(&e, &path, None, None, &["cannot read scene file"]);
        }
    }

    #[test]
    fn a_folder_is_not_a_scene_file() {
        let dir = TempDir::new("folder");
        let e = load_err(&dir.path);
        assert_error(&e, &dir.path, None, None, &["cannot read scene file"]);
    }

    #[test]
    fn malformed_toml_names_the_line() {
        let cases: &[(&str, usize, &str)] = &[
            ("[camera\nposition = [0, 0, 1]\n", 1, "expected"),
            (
                "[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0,\n",
                3,
                "array",
            ),
            (
                "[camera]\nposition = [0, 0, 1]\n\nlook_at = \n",
                4,
                "expected",
            ),
            ("# a comment\n[camera]\nposition = [0 0 1]\n", 3, "expected"),
            ("[camera]\nposition = \"open\n", 2, "string"),
            ("[camera]\n= [0, 0, 1]\n", 2, "key"),
        ];
        for &(text, line, word) in cases {
            let e = parse_err(text, SceneFormat::Toml);
            assert_error(&e, Path::new(TOML_FILE), Some(line), None, &[word]);
        }
    }

    #[test]
    fn malformed_json_names_the_line() {
        // A syntax error names the key it stopped at when there is one.
        let cases: &[(&str, usize, Option<&str>, &str)] = &[
            ("{\n  \"camera\": {\n", 3, None, "eof"),
            ("", 1, None, "eof"),
            (
                "{\n  \"render\": {}\n  \"lights\": []\n}",
                3,
                Some("lights"),
                "expected `,` or `}`",
            ),
            ("{\n  \"render\": {},\n}\n", 3, None, "trailing comma"),
            ("{\n  'camera': {}\n}", 2, None, "key"),
            ("{\n  \"camera\" {}\n}", 2, None, "expected"),
        ];
        for &(text, line, key, word) in cases {
            let e = parse_err(text, SceneFormat::Json);
            assert_error(&e, Path::new(JSON_FILE), Some(line), key, &[word]);
        }
        // Something after the document.
        let text = base().json().text + "\n{}\n";
        let e = parse_err(&text, SceneFormat::Json);
        let line = text.lines().count();
        assert_error(
            &e,
            Path::new(JSON_FILE),
            Some(line),
            None,
            &["trailing characters"],
        );
    }

    #[test]
    fn json_has_no_nan_or_infinity_literals() {
        for literal in ["NaN", "Infinity", "-Infinity"] {
            let text = base().set("spheres[0].radius", literal).json();
            let e = text.parse_err();
            let line = text.line("spheres[0].radius");
            let words = ["not a json number", "finite"];
            assert_error(
                &e,
                text.file(),
                Some(line),
                Some("spheres[0].radius"),
                &words,
            );
        }
    }

    #[test]
    fn duplicate_keys_are_errors() {
        // TOML: a syntax error at the second occurrence, naming the key.
        let text = "[camera]\nposition = [0, 0, 1]\nposition = [0, 0, 2]\n";
        let e = parse_err(text, SceneFormat::Toml);
        assert_error(
            &e,
            Path::new(TOML_FILE),
            Some(3),
            None,
            &["duplicate", "position"],
        );

        let text = base().toml().text + "\n[materials.red]\ndiffuse = [1, 1, 1]\n";
        let line = text.lines().count() - 1;
        let e = parse_err(&text, SceneFormat::Toml);
        assert_error(
            &e,
            Path::new(TOML_FILE),
            Some(line),
            None,
            &["duplicate", "red"],
        );

        // JSON: a repeated field, or a repeated material name (which
        // serde_json alone would let the last one win).
        let text =
            "{\n  \"camera\": {\n    \"position\": [0, 0, 1],\n    \"position\": [0, 0, 2]\n  }\n}";
        let e = parse_err(text, SceneFormat::Json);
        assert_error(
            &e,
            Path::new(JSON_FILE),
            Some(4),
            Some("camera.position"),
            &["duplicate"],
        );

        let text = "{\n  \"camera\": {\"position\": [0, 0, 1], \"look_at\": [0, 0, 0]},\n  \
                    \"lights\": [{\"position\": [1, 1, 1]}],\n  \"materials\": {\n    \
                    \"red\": {\"diffuse\": [1, 0, 0]},\n    \"red\": {\"diffuse\": [0, 1, 0]}\n  }\n}";
        let e = parse_err(text, SceneFormat::Json);
        assert_error(
            &e,
            Path::new(JSON_FILE),
            Some(6),
            Some("materials.red"),
            &["red", "twice"],
        );
    }

    #[test]
    fn the_extension_picks_the_format() {
        let dir = TempDir::new("ext");
        let json = base().json().text;
        let toml = base().toml().text;
        let expected = assert_accepted(&base());
        // `.json` in any case is JSON; anything else is TOML.
        assert_eq!(load_ok(&dir.write("a.json", &json)), expected);
        assert_eq!(load_ok(&dir.write("b.JSON", &json)), expected);
        assert_eq!(load_ok(&dir.write("c.toml", &toml)), expected);
        assert_eq!(load_ok(&dir.write("d.scene", &toml)), expected);
        assert_eq!(load_ok(&dir.write("noextension", &toml)), expected);
        // JSON in a .toml file is read as TOML, and fails as TOML.
        let path = dir.write("e.toml", &json);
        let e = load_err(&path);
        assert_eq!(e.file, path);
        assert_eq!(e.line, Some(1), "{e}");
        assert_eq!(e.key, None, "{e}");
    }

    #[test]
    fn errors_from_load_scene_name_the_real_file() {
        let dir = TempDir::new("real");
        let doc = two_spheres().set("spheres[1].radius", "-1");
        for (name, text) in [("s.toml", doc.toml()), ("s.json", doc.json())] {
            let path = dir.write(name, &text.text);
            let e = load_err(&path);
            let line = text.line("spheres[1].radius");
            assert_error(&e, &path, Some(line), Some("spheres[1].radius"), &["> 0"]);
            assert!(e
                .to_string()
                .starts_with(&format!("{}:{line}: spheres[1].radius: ", path.display())));
        }
    }
}

// ============================================================== schema: keys and types

mod schema {
    use super::*;

    #[test]
    fn unknown_keys_are_errors_naming_the_key() {
        let cases: &[(&str, &str)] = &[
            ("foo", "1"),
            ("camera.fov", "60"),
            ("render.gamma", "2.2"),
            ("lights[0].colour", "[1, 1, 1]"),
            ("materials.red.shine", "3"),
            ("materials.blue.Diffuse", "[1, 1, 1]"),
            ("spheres[1].color", "[1, 0, 0]"),
            ("triangles[0].normal", "[0, 0, 1]"),
            ("meshes[0].rotation", "[0, 0, 90]"),
        ];
        for &(key, value) in cases {
            let doc = with_mesh()
                .set("spheres[1].center", "[1, 0, -1]")
                .set("spheres[1].radius", "0.25")
                .set("spheres[1].material", "\"blue\"")
                .set(key, value);
            let name = key.rsplit('.').next().unwrap();
            assert_rejected(
                &doc,
                key,
                &["unknown field", &format!("`{name}`"), "expected"],
            );
        }
    }

    #[test]
    fn wrong_types_are_errors_naming_the_key() {
        // (key set, value, key reported, words)
        let cases: &[(&str, &str, &str, &[&str])] = &[
            (
                "spheres[1].radius",
                "\"big\"",
                "spheres[1].radius",
                &["invalid type", "string"],
            ),
            (
                "spheres[1].center",
                "1",
                "spheres[1].center",
                &["invalid type"],
            ),
            (
                "spheres[1].material",
                "3",
                "spheres[1].material",
                &["invalid type"],
            ),
            (
                "camera.position",
                "[0, 0]",
                "camera.position",
                &["invalid length 2", "3"],
            ),
            (
                "camera.position",
                "[0, 0, 1, 1]",
                "camera.position",
                &["invalid length"],
            ),
            (
                "camera.position",
                "[0, \"a\", 1]",
                "camera.position[1]",
                &["invalid type"],
            ),
            ("camera.up", "\"y\"", "camera.up", &["invalid type"]),
            ("camera.vfov", "[60]", "camera.vfov", &["invalid type"]),
            ("render.width", "1.5", "render.width", &["invalid type"]),
            ("render.width", "\"800\"", "render.width", &["invalid type"]),
            ("render.height", "-1", "render.height", &["invalid value"]),
            (
                "render.max_depth",
                "2.5",
                "render.max_depth",
                &["invalid type"],
            ),
            ("render.samples", "-4", "render.samples", &["invalid value"]),
            (
                "render.background",
                "0",
                "render.background",
                &["invalid type"],
            ),
            (
                "render.shadow_mode",
                "\"hard\"",
                "render.shadow_mode",
                &["unknown variant", "ambient", "seed"],
            ),
            (
                "render.shadow_mode",
                "\"Seed\"",
                "render.shadow_mode",
                &["unknown variant"],
            ),
            (
                "render.shadow_mode",
                "1",
                "render.shadow_mode",
                &["invalid type"],
            ),
            (
                "lights[0].ambient",
                "1",
                "lights[0].ambient",
                &["invalid type"],
            ),
            (
                "materials.red.diffuse",
                "0.5",
                "materials.red.diffuse",
                &["invalid type"],
            ),
            (
                "materials.red.shininess",
                "\"shiny\"",
                "materials.red.shininess",
                &["invalid type"],
            ),
            (
                "triangles[0].vertices",
                "[[0, 0, 0], [1, 0, 0]]",
                "triangles[0].vertices",
                &["invalid length"],
            ),
            (
                "triangles[0].vertices",
                "[0, 0, 0]",
                "triangles[0].vertices[0]",
                &["invalid type"],
            ),
            ("meshes[0].path", "7", "meshes[0].path", &["invalid type"]),
            (
                "meshes[0].scale",
                "\"big\"",
                "meshes[0].scale",
                &["a number or an array of 3 numbers"],
            ),
            (
                "meshes[0].scale",
                "[1, 2]",
                "meshes[0].scale",
                &["invalid length"],
            ),
            (
                "meshes[0].scale",
                "[1, 2, 3, 4]",
                "meshes[0].scale",
                &["invalid length"],
            ),
            (
                "meshes[0].rotate",
                "90",
                "meshes[0].rotate",
                &["invalid type"],
            ),
            ("lights", "3", "lights", &["invalid type"]),
            (
                "materials",
                "[]",
                "materials",
                &["invalid type", "materials"],
            ),
            (
                "render",
                "5",
                "render",
                &["invalid type", "a [render] table"],
            ),
            (
                "camera",
                "[0, 0, 1]",
                "camera",
                &["invalid type", "a [camera] table"],
            ),
            // A table is never an array of its fields in order.
            (
                "camera",
                "[[0, 0, 1], [0, 0, 0]]",
                "camera",
                &["invalid type", "a [camera] table"],
            ),
            (
                "spheres",
                "[[[0, 0, 0], 1, \"red\"]]",
                "spheres[0]",
                &["invalid type", "a [[spheres]] table"],
            ),
            (
                "lights",
                "[1]",
                "lights[0]",
                &["invalid type", "a [[lights]] table"],
            ),
            (
                "spheres",
                "[[0, 0, 0]]",
                "spheres[0]",
                &["invalid type", "a [[spheres]] table"],
            ),
            (
                "triangles",
                "[\"a\"]",
                "triangles[0]",
                &["invalid type", "a [[triangles]] table"],
            ),
            (
                "meshes",
                "[2]",
                "meshes[0]",
                &["invalid type", "a [[meshes]] table"],
            ),
            (
                "materials.red",
                "1",
                "materials.red",
                &["invalid type", "a material table"],
            ),
        ];
        for &(set, value, key, words) in cases {
            let doc = with_mesh()
                .set("spheres[1].center", "[1, 0, -1]")
                .set("spheres[1].radius", "0.25")
                .set("spheres[1].material", "\"blue\"")
                .set(set, value);
            assert_rejected(&doc, key, words);
        }
    }

    #[test]
    fn missing_required_keys_name_their_table() {
        let cases: &[(&str, &str, &str)] = &[
            ("camera.position", "camera", "`position`"),
            ("camera.look_at", "camera", "`look_at`"),
            ("lights[0].position", "lights[0]", "`position`"),
            ("materials.red.diffuse", "materials.red", "`diffuse`"),
            ("spheres[1].radius", "spheres[1]", "`radius`"),
            ("spheres[1].center", "spheres[1]", "`center`"),
            ("spheres[1].material", "spheres[1]", "`material`"),
            ("triangles[0].vertices", "triangles[0]", "`vertices`"),
            ("triangles[0].material", "triangles[0]", "`material`"),
            ("meshes[0].path", "meshes[0]", "`path`"),
        ];
        for &(removed, table, word) in cases {
            let doc = with_mesh()
                .set("materials.red.ambient", "[0, 0, 0]")
                .set("spheres[1].center", "[1, 0, -1]")
                .set("spheres[1].radius", "0.25")
                .set("spheres[1].material", "\"blue\"")
                .remove(removed);
            for text in doc.both() {
                let e = text.parse_err();
                let line = text.table_line(table);
                assert_error(
                    &e,
                    text.file(),
                    Some(line),
                    Some(table),
                    &["missing field", word],
                );
            }
        }
    }

    #[test]
    fn a_json_document_must_be_an_object() {
        for text in ["[]", "3", "null", "\"scene\""] {
            let e = parse_err(text, SceneFormat::Json);
            assert_error(
                &e,
                Path::new(JSON_FILE),
                None,
                None,
                &["invalid type", "expected a scene"],
            );
        }
    }

    #[test]
    fn a_missing_camera_is_an_error_about_the_whole_file() {
        for text in base().remove("camera").both() {
            let e = text.parse_err();
            assert_error(&e, text.file(), None, None, &["missing field", "`camera`"]);
        }
        for format in [SceneFormat::Toml, SceneFormat::Json] {
            let text = if format == SceneFormat::Json {
                "{}"
            } else {
                ""
            };
            let e = parse_err(text, format);
            assert_error(
                &e,
                file_of(format),
                None,
                None,
                &["missing field", "`camera`"],
            );
        }
    }

    #[test]
    fn at_least_one_light_is_required() {
        // No lights key at all: no line to name.
        for text in base().remove("lights").both() {
            let e = text.parse_err();
            assert_error(&e, text.file(), None, Some("lights"), &["at least one"]);
        }
        // An empty list: its line.
        assert_rejected(&base().set("lights", "[]"), "lights", &["at least one"]);
    }

    #[test]
    fn every_optional_key_may_be_left_out() {
        let doc = Doc::default()
            .set("camera.position", "[0, 0, 1]")
            .set("camera.look_at", "[0, 0, 0]")
            .set("lights[0].position", "[5, 5, 5]");
        let scene = assert_accepted(&doc);
        assert!(scene.materials.is_empty());
        assert!(scene.spheres.is_empty());
        assert!(scene.triangles.is_empty());
        assert_eq!(scene.object_count(), 0);
    }
}

// ============================================================== numbers

mod numbers {
    use super::*;

    /// (key set, value with `X` for the bad number, key reported).
    const NUMBER_SITES: &[(&str, &str, &str)] = &[
        ("camera.position", "[0, X, 1]", "camera.position[1]"),
        ("camera.look_at", "[X, 0, 0]", "camera.look_at[0]"),
        ("camera.up", "[0, 1, X]", "camera.up[2]"),
        ("camera.vfov", "X", "camera.vfov"),
        ("render.min_intensity", "X", "render.min_intensity"),
        ("render.background", "[0, X, 0]", "render.background[1]"),
        ("lights[0].position", "[X, 5, 5]", "lights[0].position[0]"),
        ("lights[0].ambient", "[1, 1, X]", "lights[0].ambient[2]"),
        ("lights[0].diffuse", "[1, X, 1]", "lights[0].diffuse[1]"),
        ("lights[0].specular", "[X, 1, 1]", "lights[0].specular[0]"),
        (
            "materials.red.ambient",
            "[X, 0, 0]",
            "materials.red.ambient[0]",
        ),
        (
            "materials.red.diffuse",
            "[0, X, 0]",
            "materials.red.diffuse[1]",
        ),
        (
            "materials.red.specular",
            "[0, 0, X]",
            "materials.red.specular[2]",
        ),
        ("materials.red.shininess", "X", "materials.red.shininess"),
        ("materials.red.reflection", "X", "materials.red.reflection"),
        ("spheres[0].center", "[0, 0, X]", "spheres[0].center[2]"),
        ("spheres[0].radius", "X", "spheres[0].radius"),
        (
            "triangles[0].vertices",
            "[[0, 0, -2], [1, X, -2], [0, 1, -2]]",
            "triangles[0].vertices[1][1]",
        ),
        ("meshes[0].scale", "X", "meshes[0].scale"),
        ("meshes[0].scale", "[1, X, 1]", "meshes[0].scale[1]"),
        ("meshes[0].rotate", "[X, 0, 0]", "meshes[0].rotate[0]"),
        ("meshes[0].translate", "[0, 0, X]", "meshes[0].translate[2]"),
    ];

    #[test]
    fn nan_and_inf_are_errors_anywhere_in_toml() {
        for &(set, value, key) in NUMBER_SITES {
            for bad in [
                "nan", "+nan", "-nan", "inf", "+inf", "-inf", "1e999", "-1e999",
            ] {
                let text = with_mesh().set(set, &value.replace('X', bad)).toml();
                assert_rejected_text(&text, key, &["finite"]);
            }
        }
    }

    #[test]
    fn out_of_range_numbers_are_errors_anywhere_in_json() {
        // JSON has no NaN or infinity; a number too large for f64 is how one
        // would try, and serde_json rejects it.
        for &(set, value, key) in NUMBER_SITES {
            for bad in ["1e999", "-1e999", "1.5e400"] {
                let text = with_mesh().set(set, &value.replace('X', bad)).json();
                assert_rejected_text(&text, key, &["out of range", "finite"]);
            }
        }
    }

    #[test]
    fn integers_are_accepted_wherever_a_number_is_expected() {
        let ints = base()
            .set("camera.position", "[0, 0, 4]")
            .set("camera.up", "[0, 2, 0]")
            .set("camera.vfov", "90")
            .set("render.min_intensity", "1")
            .set("render.background", "[0, 0, 1]")
            .set("lights[0].ambient", "[0, 0, 0]")
            .set("lights[0].diffuse", "[1, 1, 1]")
            .set("lights[0].specular", "[2, 2, 2]")
            .set("materials.red.diffuse", "[1, 0, 0]")
            .set("materials.red.specular", "[1, 1, 1]")
            .set("materials.red.shininess", "100")
            .set("materials.red.reflection", "1")
            .set("spheres[0].center", "[0, 0, -3]")
            .set("spheres[0].radius", "2");
        let floats = base()
            .set("camera.position", "[0.0, 0.0, 4.0]")
            .set("camera.up", "[0.0, 2.0, 0.0]")
            .set("camera.vfov", "90.0")
            .set("render.min_intensity", "1.0")
            .set("render.background", "[0.0, 0.0, 1.0]")
            .set("lights[0].ambient", "[0.0, 0.0, 0.0]")
            .set("lights[0].diffuse", "[1.0, 1.0, 1.0]")
            .set("lights[0].specular", "[2.0, 2.0, 2.0]")
            .set("materials.red.diffuse", "[1.0, 0.0, 0.0]")
            .set("materials.red.specular", "[1.0, 1.0, 1.0]")
            .set("materials.red.shininess", "100.0")
            .set("materials.red.reflection", "1.0")
            .set("spheres[0].center", "[0.0, 0.0, -3.0]")
            .set("spheres[0].radius", "2.0");
        let scene = assert_accepted(&ints);
        assert_eq!(scene, assert_accepted(&floats));
        assert_eq!(scene.camera.vfov_degrees, 90.0);
        assert_eq!(scene.spheres[0].radius, 2.0);
        assert_eq!(scene.lights[0].specular, DVec3::splat(2.0));
    }

    #[test]
    fn exponents_and_signs_are_numbers() {
        let doc = base()
            .set("spheres[0].radius", "5e-1")
            .set("spheres[0].center", "[-0.0, 1E1, -1.25e+2]");
        let scene = assert_accepted(&doc);
        assert_eq!(scene.spheres[0].radius, 0.5);
        assert_eq!(scene.spheres[0].center, DVec3::new(0.0, 10.0, -125.0));
    }
}

// ============================================================== camera

mod camera {
    use super::*;

    #[test]
    fn defaults() {
        let scene = assert_accepted(&base());
        assert_eq!(
            scene.camera,
            Camera {
                position: DVec3::new(0.0, 0.0, 1.0),
                look_at: DVec3::ZERO,
                up: DVec3::Y,
                vfov_degrees: 60.0,
            }
        );
    }

    #[test]
    fn vfov_must_be_inside_0_180() {
        for bad in ["0", "0.0", "-10", "180", "180.0", "200"] {
            assert_rejected(
                &base().set("camera.vfov", bad),
                "camera.vfov",
                &["(0, 180)"],
            );
        }
        for (good, value) in [
            ("0.001", 0.001),
            ("1", 1.0),
            ("58.7155", 58.7155),
            ("179.999", 179.999),
        ] {
            let scene = assert_accepted(&base().set("camera.vfov", good));
            assert_eq!(scene.camera.vfov_degrees, value);
        }
    }

    #[test]
    fn up_must_not_be_parallel_to_the_view_direction() {
        // The view direction is -z.
        for bad in [
            "[0, 0, -1]",
            "[0, 0, 1]",
            "[0, 0, 7.5]",
            "[0, 0, 0]",
            "[0, 1e-12, 1]",
        ] {
            assert_rejected(
                &base().set("camera.up", bad),
                "camera.up",
                &["parallel", "look_at - position"],
            );
        }
        // Any other up is fine; it need not be unit length or perpendicular.
        for good in [
            "[0, 1, 0]",
            "[1, 0, 0]",
            "[0, 3, 3]",
            "[0, 1e-6, 1]",
            "[0, -2, 0]",
        ] {
            assert_accepted(&base().set("camera.up", good));
        }
        let scene = assert_accepted(&base().set("camera.up", "[0, 3, 3]"));
        assert_eq!(scene.camera.up, DVec3::new(0.0, 3.0, 3.0));
    }

    #[test]
    fn the_default_up_is_checked_too_and_says_so() {
        // Looking straight down: the default up [0, 1, 0] is parallel. The
        // file has no camera.up, so the error is on the [camera] line.
        let doc = base().set("camera.position", "[0, 5, 0]");
        for text in doc.both() {
            let e = text.parse_err();
            let line = text.line("camera");
            assert_error(
                &e,
                text.file(),
                Some(line),
                Some("camera.up"),
                &["parallel", "default"],
            );
        }
        assert_accepted(&doc.set("camera.up", "[0, 0, -1]"));
    }

    #[test]
    fn look_at_must_differ_from_position() {
        let doc = base().set("camera.look_at", "[0, 0, 1]");
        assert_rejected(&doc, "camera.look_at", &["differ", "position"]);
        // A tiny or a large view direction is fine.
        assert_accepted(&base().set("camera.position", "[0, 0, 1e-300]"));
        assert_accepted(&base().set("camera.position", "[0, 0, 1e15]"));
    }

    /// The GPU computes in f32 and squares distances: coordinates beyond
    /// ±1e15 (and radii above 1e15) are refused, naming the component.
    #[test]
    fn coordinates_beyond_f32_range_are_rejected() {
        assert_rejected(
            &base().set("camera.position", "[0, 0, 1e300]"),
            "camera.position[2]",
            &["1e15", "f32"],
        );
        assert_rejected(
            &base().set("camera.look_at", "[-2e15, 0, 0]"),
            "camera.look_at[0]",
            &["1e15"],
        );
    }
}

// ============================================================== render

mod render {
    use super::*;

    const DEFAULTS: RenderSettings = RenderSettings {
        width: 800,
        height: 600,
        min_intensity: 0.05,
        max_depth: 10,
        background: DVec3::ZERO,
        shadow_mode: ShadowMode::Ambient,
        samples: 1,
    };

    #[test]
    fn a_missing_or_empty_render_table_gives_the_defaults() {
        assert_eq!(assert_accepted(&base()).render, DEFAULTS);
        let toml = format!("[render]\n\n{}", base().toml().text);
        assert_eq!(parse_ok(&toml, SceneFormat::Toml).render, DEFAULTS);
        let json = base().json().text.replacen('{', "{\n  \"render\": {},", 1);
        assert_eq!(parse_ok(&json, SceneFormat::Json).render, DEFAULTS);
        assert_eq!(DEFAULTS.samples_per_axis(), 1);
    }

    #[test]
    fn every_render_key_is_read() {
        let doc = base()
            .set("render.width", "1920")
            .set("render.height", "1080")
            .set("render.min_intensity", "0.25")
            .set("render.max_depth", "3")
            .set("render.background", "[0.1, 0.2, 0.3]")
            .set("render.shadow_mode", "\"seed\"")
            .set("render.samples", "16");
        let render = assert_accepted(&doc).render;
        assert_eq!(
            render,
            RenderSettings {
                width: 1920,
                height: 1080,
                min_intensity: 0.25,
                max_depth: 3,
                background: DVec3::new(0.1, 0.2, 0.3),
                shadow_mode: ShadowMode::Seed,
                samples: 16,
            }
        );
        assert_eq!(render.samples_per_axis(), 4);
        let doc = base().set("render.shadow_mode", "\"ambient\"");
        assert_eq!(
            assert_accepted(&doc).render.shadow_mode,
            ShadowMode::Ambient
        );
    }

    #[test]
    fn width_and_height_must_be_1_to_16384() {
        for key in ["render.width", "render.height"] {
            for bad in ["0", "16385", "100000"] {
                assert_rejected(&base().set(key, bad), key, &["1..=16384", bad]);
            }
            for good in ["1", "16384"] {
                assert_accepted(&base().set(key, good));
            }
        }
        // Larger than a u32: a type error, still on the key.
        let doc = base().set("render.width", "5000000000");
        assert_rejected(&doc, "render.width", &["invalid value"]);
    }

    #[test]
    fn min_intensity_must_be_in_0_1() {
        for bad in ["-0.1", "1.01", "2", "-1e-9"] {
            assert_rejected(
                &base().set("render.min_intensity", bad),
                "render.min_intensity",
                &["[0, 1]"],
            );
        }
        for (good, value) in [("0", 0.0), ("1", 1.0), ("0.5", 0.5)] {
            let scene = assert_accepted(&base().set("render.min_intensity", good));
            assert_eq!(scene.render.min_intensity, value);
        }
    }

    #[test]
    fn max_depth_must_be_1_to_64() {
        for bad in ["0", "65", "1000"] {
            assert_rejected(
                &base().set("render.max_depth", bad),
                "render.max_depth",
                &["1..=64", bad],
            );
        }
        for good in [1, 64] {
            let scene = assert_accepted(&base().set("render.max_depth", &good.to_string()));
            assert_eq!(scene.render.max_depth, good);
        }
    }

    #[test]
    fn samples_must_be_a_perfect_square() {
        for bad in ["0", "2", "3", "5", "8", "15", "17", "99", "4294967295"] {
            assert_rejected(
                &base().set("render.samples", bad),
                "render.samples",
                &["perfect square", bad],
            );
        }
        for k in [1u32, 2, 3, 4, 5, 8, 16] {
            let samples = k * k;
            let scene = assert_accepted(&base().set("render.samples", &samples.to_string()));
            assert_eq!(scene.render.samples, samples);
            assert_eq!(scene.render.samples_per_axis(), k);
        }
    }

    #[test]
    fn background_is_a_colour() {
        assert_rejected(
            &base().set("render.background", "[0, -0.5, 0]"),
            "render.background",
            &[">= 0"],
        );
        let scene = assert_accepted(&base().set("render.background", "[0, 0, 2]"));
        assert_eq!(scene.render.background, DVec3::new(0.0, 0.0, 2.0));
    }
}

// ============================================================== lights, materials, spheres, triangles

mod objects {
    use super::*;

    #[test]
    fn light_colours_default_to_one() {
        let scene = assert_accepted(&base());
        assert_eq!(
            scene.lights,
            vec![Light {
                position: DVec3::splat(5.0),
                ambient: DVec3::ONE,
                diffuse: DVec3::ONE,
                specular: DVec3::ONE,
            }]
        );
        let doc = base()
            .set("lights[0].diffuse", "[0.5, 0.5, 0.5]")
            .set("lights[1].position", "[-5, 5, 5]")
            .set("lights[1].ambient", "[0, 0, 0]");
        let lights = assert_accepted(&doc).lights;
        assert_eq!(lights.len(), 2);
        assert_eq!(lights[0].diffuse, DVec3::splat(0.5));
        assert_eq!(lights[0].ambient, DVec3::ONE);
        assert_eq!(lights[1].position, DVec3::new(-5.0, 5.0, 5.0));
        assert_eq!(lights[1].ambient, DVec3::ZERO);
        assert_eq!(lights[1].specular, DVec3::ONE);
    }

    #[test]
    fn material_defaults_and_values() {
        let doc = base()
            .set("materials.red.ambient", "[0.1, 0, 0]")
            .set("materials.red.specular", "[1, 1, 1]")
            .set("materials.red.shininess", "100.0")
            .set("materials.red.reflection", "0.5");
        let scene = assert_accepted(&doc);
        let find = |name: &str| {
            scene
                .materials
                .iter()
                .find(|m| m.name == name)
                .unwrap()
                .clone()
        };
        assert_eq!(
            find("red"),
            Material {
                name: "red".into(),
                ambient: DVec3::new(0.1, 0.0, 0.0),
                diffuse: DVec3::new(0.7, 0.0, 0.0),
                specular: DVec3::ONE,
                shininess: 100.0,
                reflection: 0.5,
            }
        );
        assert_eq!(
            find("blue"),
            Material {
                name: "blue".into(),
                ambient: DVec3::ZERO,
                diffuse: DVec3::new(0.0, 0.0, 0.7),
                specular: DVec3::ZERO,
                shininess: 0.0,
                reflection: 0.0,
            }
        );
        assert_eq!(scene.materials.len(), 2);
    }

    #[test]
    fn objects_refer_to_materials_by_name() {
        let scene = assert_accepted(&two_spheres());
        let name = |index: u32| scene.materials[index as usize].name.as_str();
        assert_eq!(
            scene.spheres[0],
            Sphere {
                center: DVec3::new(0.0, 0.0, -1.0),
                radius: 0.5,
                material: scene.spheres[0].material,
            }
        );
        assert_eq!(name(scene.spheres[0].material), "red");
        assert_eq!(name(scene.spheres[1].material), "blue");
        assert_eq!(
            scene.triangles,
            vec![Triangle::flat(
                [
                    DVec3::new(0.0, 0.0, -2.0),
                    DVec3::new(1.0, 0.0, -2.0),
                    DVec3::new(0.0, 1.0, -2.0)
                ],
                scene.triangles[0].material,
            )]
        );
        assert_eq!(name(scene.triangles[0].material), "blue");
        assert_eq!(scene.object_count(), 3);
    }

    #[test]
    fn material_names_may_need_quoting() {
        // TOML needs `[materials."brushed steel"]`; the Doc writer does not
        // quote, so this one is written by hand.
        let toml = "[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0, 0]\n[[lights]]\nposition = [1, 1, 1]\n\
                    [materials.\"brushed steel\"]\ndiffuse = [0.5, 0.5, 0.5]\n\
                    [[spheres]]\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"brushed steel\"\n";
        let scene = parse_ok(toml, SceneFormat::Toml);
        assert_eq!(scene.materials[0].name, "brushed steel");
        assert_eq!(scene.spheres[0].material, 0);
    }

    #[test]
    fn unknown_materials_are_errors() {
        let cases = [
            two_spheres().set("spheres[1].material", "\"green\""),
            two_triangles().set("triangles[1].material", "\"green\""),
            with_mesh().set("meshes[0].material", "\"green\""),
        ];
        let keys = [
            "spheres[1].material",
            "triangles[1].material",
            "meshes[0].material",
        ];
        for (doc, key) in cases.iter().zip(keys) {
            assert_rejected(doc, key, &["unknown material", "\"green\"", "blue, red"]);
        }
        // Names are case-sensitive.
        let doc = two_spheres().set("spheres[1].material", "\"Red\"");
        assert_rejected(
            &doc,
            "spheres[1].material",
            &["unknown material", "\"Red\""],
        );
        // With no materials at all the message says so.
        let doc = base()
            .remove("materials")
            .remove("triangles")
            .set("spheres[0].material", "\"red\"");
        assert_rejected(&doc, "spheres[0].material", &["unknown material", "none"]);
    }

    #[test]
    fn radius_must_be_positive() {
        for bad in ["0", "0.0", "-0.5", "-1e-300"] {
            let doc = two_spheres().set("spheres[1].radius", bad);
            assert_rejected(&doc, "spheres[1].radius", &["> 0"]);
        }
        let scene = assert_accepted(&two_spheres().set("spheres[1].radius", "1e-9"));
        assert_eq!(scene.spheres[1].radius, 1e-9);
    }

    #[test]
    fn zero_area_triangles_are_errors() {
        for bad in [
            "[[0, 0, 0], [1, 1, 1], [2, 2, 2]]",           // collinear
            "[[0, 0, 0], [1, 0, 0], [1, 0, 0]]",           // a repeated vertex
            "[[3, 3, 3], [3, 3, 3], [3, 3, 3]]",           // a point
            "[[0, 0, 0], [1e-200, 0, 0], [0, 1e-200, 0]]", // too small for f64 to see any area
        ] {
            let doc = two_triangles().set("triangles[1].vertices", bad);
            assert_rejected(&doc, "triangles[1].vertices", &["zero area"]);
        }
        // Thin is not zero.
        assert_accepted(&two_triangles().set(
            "triangles[1].vertices",
            "[[0, 0, 0], [1, 0, 0], [2, 1e-9, 0]]",
        ));
    }

    #[test]
    fn colours_must_not_be_negative() {
        let keys = [
            "lights[0].ambient",
            "lights[0].diffuse",
            "lights[0].specular",
            "materials.red.ambient",
            "materials.red.diffuse",
            "materials.red.specular",
            "render.background",
        ];
        for key in keys {
            let doc = base().set(key, "[0.5, -0.01, 0.5]");
            assert_rejected(&doc, key, &["colour", ">= 0"]);
        }
        // No upper limit: colours are linear and may exceed 1.
        let scene = assert_accepted(&base().set("lights[0].diffuse", "[4, 4, 4]"));
        assert_eq!(scene.lights[0].diffuse, DVec3::splat(4.0));
    }

    #[test]
    fn reflection_must_be_in_0_1_and_shininess_non_negative() {
        for bad in ["-0.1", "1.5"] {
            let doc = base().set("materials.blue.reflection", bad);
            assert_rejected(&doc, "materials.blue.reflection", &["[0, 1]"]);
        }
        for good in ["0", "1", "0.25"] {
            assert_accepted(&base().set("materials.blue.reflection", good));
        }
        let doc = base().set("materials.blue.shininess", "-1");
        assert_rejected(&doc, "materials.blue.shininess", &[">= 0"]);
        assert_accepted(&base().set("materials.blue.shininess", "0"));
        assert_accepted(&base().set("materials.blue.shininess", "10000"));
    }
}

// ============================================================== meshes and OBJ files

mod meshes {
    use super::*;

    /// Writes `scene.toml` in `dir` (the base scene plus `[[meshes]]` with the
    /// given keys, in the given order) and returns its path.
    fn mesh_scene(dir: &TempDir, mesh_keys: &[(&str, &str)]) -> PathBuf {
        let mut doc = base();
        for (key, value) in mesh_keys {
            doc = doc.set(&format!("meshes[0].{key}"), value);
        }
        dir.write("scene.toml", &doc.toml().text)
    }

    /// The one triangle of models/tri.obj after the mesh transform.
    #[track_caller]
    fn transformed(mesh_keys: &[(&str, &str)]) -> [DVec3; 3] {
        let dir = TempDir::new("xform");
        dir.write("models/tri.obj", ONE_TRIANGLE_OBJ);
        let mut keys = vec![("path", "\"models/tri.obj\""), ("material", "\"red\"")];
        keys.extend_from_slice(mesh_keys);
        let scene = load_ok(&mesh_scene(&dir, &keys));
        // triangles[0] is the scene's own [[triangles]] entry; meshes come after.
        assert_eq!(scene.triangles.len(), 2);
        scene.triangles[1].vertices
    }

    #[track_caller]
    fn assert_vertices(got: [DVec3; 3], want: [[f64; 3]; 3]) {
        for (g, w) in got.into_iter().zip(want) {
            assert_close(g, DVec3::from_array(w));
        }
    }

    #[test]
    fn no_transform_is_the_identity() {
        assert_vertices(transformed(&[]), [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.]]);
        let explicit = [
            ("scale", "1"),
            ("rotate", "[0, 0, 0]"),
            ("translate", "[0, 0, 0]"),
        ];
        assert_vertices(
            transformed(&explicit),
            [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.]],
        );
    }

    #[test]
    fn rotations_are_degrees_about_the_world_axes() {
        // z by 90: x -> y, y -> -x.
        assert_vertices(
            transformed(&[("rotate", "[0, 0, 90]")]),
            [[0., 0., 0.], [0., 1., 0.], [-1., 0., 0.]],
        );
        // x by 90: y -> z.
        assert_vertices(
            transformed(&[("rotate", "[90, 0, 0]")]),
            [[0., 0., 0.], [1., 0., 0.], [0., 0., 1.]],
        );
        // y by 90: x -> -z.
        assert_vertices(
            transformed(&[("rotate", "[0, 90, 0]")]),
            [[0., 0., 0.], [0., 0., -1.], [0., 1., 0.]],
        );
    }

    #[test]
    fn rotations_apply_x_then_y_then_z() {
        // Rz * Ry * Rx: x (1,0,0) -> Rx (1,0,0) -> Ry (0,0,-1) -> Rz (0,0,-1);
        //               y (0,1,0) -> Rx (0,0,1) -> Ry (1,0,0)  -> Rz (0,1,0).
        // (z first would send x to (0,0,1).)
        assert_vertices(
            transformed(&[("rotate", "[90, 90, 90]")]),
            [[0., 0., 0.], [0., 0., -1.], [0., 1., 0.]],
        );
        // Rz * Rx alone: y -> z under Rx, and z stays under Rz.
        assert_vertices(
            transformed(&[("rotate", "[90, 0, 90]")]),
            [[0., 0., 0.], [0., 1., 0.], [0., 0., 1.]],
        );
    }

    #[test]
    fn scale_is_a_number_or_per_axis_and_comes_first() {
        assert_vertices(
            transformed(&[("scale", "[2, 1, 1]")]),
            [[0., 0., 0.], [2., 0., 0.], [0., 1., 0.]],
        );
        assert_vertices(
            transformed(&[("scale", "3")]),
            [[0., 0., 0.], [3., 0., 0.], [0., 3., 0.]],
        );
        assert_vertices(
            transformed(&[("scale", "0.5")]),
            [[0., 0., 0.], [0.5, 0., 0.], [0., 0.5, 0.]],
        );
        // Negative scales mirror; only 0 is refused.
        assert_vertices(
            transformed(&[("scale", "[-1, 1, 1]")]),
            [[0., 0., 0.], [-1., 0., 0.], [0., 1., 0.]],
        );
        // Scale before rotation: x is stretched, then turned onto y.
        assert_vertices(
            transformed(&[("scale", "[2, 1, 1]"), ("rotate", "[0, 0, 90]")]),
            [[0., 0., 0.], [0., 2., 0.], [-1., 0., 0.]],
        );
    }

    #[test]
    fn translate_comes_last() {
        assert_vertices(
            transformed(&[("translate", "[1, 2, 3]")]),
            [[1., 2., 3.], [2., 2., 3.], [1., 3., 3.]],
        );
        // v' = Rz * Ry * Rx * (scale * v) + translate, keys in any order.
        assert_vertices(
            transformed(&[
                ("translate", "[1, 2, 3]"),
                ("rotate", "[0, 0, 90]"),
                ("scale", "2"),
            ]),
            [[1., 2., 3.], [1., 4., 3.], [-1., 2., 3.]],
        );
    }

    #[test]
    fn a_zero_scale_is_an_error() {
        for bad in ["0", "[1, 0, 1]", "[0, 0, 0]", "-0.0"] {
            assert_rejected(
                &with_mesh().set("meshes[0].scale", bad),
                "meshes[0].scale",
                &["non-zero"],
            );
        }
    }

    #[test]
    fn extreme_transforms() {
        let dir = TempDir::new("extreme");
        dir.write("tri.obj", ONE_TRIANGLE_OBJ);
        let mesh = |scale: &str| {
            base()
                .set("meshes[0].path", "\"tri.obj\"")
                .set("meshes[0].material", "\"red\"")
                .set("meshes[0].scale", scale)
                .toml()
        };
        // A triangle flattened below what f64 can hold is skipped, like any
        // zero-area face of an OBJ file.
        let scene = load_ok(&dir.write("flat.toml", &mesh("[1e-200, 1e-200, 1]").text));
        assert_eq!(scene.triangles.len(), 1);
        // A vertex sent past the largest f64 is an error on the scale.
        dir.write("tri.obj", "v 0 0 0\nv 1e300 0 0\nv 0 1 0\nf 1 2 3\n");
        let text = mesh("1e300");
        let path = dir.write("huge.toml", &text.text);
        let line = Some(text.line("meshes[0].scale"));
        let e = load_err(&path);
        assert_error(&e, &path, line, Some("meshes[0].scale"), &["non-finite"]);
    }

    #[test]
    fn mesh_paths_are_relative_to_the_scene_file() {
        let dir = TempDir::new("relative");
        dir.write("sub/models/tri.obj", ONE_TRIANGLE_OBJ);
        dir.write("shared/tri.obj", ONE_TRIANGLE_OBJ);
        let doc = base()
            .set("meshes[0].path", "\"models/tri.obj\"")
            .set("meshes[0].material", "\"red\"")
            .set("meshes[1].path", "\"../shared/tri.obj\"")
            .set("meshes[1].material", "\"blue\"");
        for (name, text) in [
            ("sub/scene.toml", doc.toml()),
            ("sub/scene.json", doc.json()),
        ] {
            let scene = load_ok(&dir.write(name, &text.text));
            assert_eq!(scene.triangles.len(), 3);
        }
        // An absolute path is used as it is.
        let abs = dir.join("shared/tri.obj");
        let doc = base()
            .set("meshes[0].path", &format!("{:?}", abs.to_str().unwrap()))
            .set("meshes[0].material", "\"red\"");
        let scene = load_ok(&dir.write("elsewhere/scene.toml", &doc.toml().text));
        assert_eq!(scene.triangles.len(), 2);
    }

    #[test]
    fn a_material_override_applies_to_every_face_and_skips_the_mtl() {
        let dir = TempDir::new("override");
        copy_torus(&dir, "models");
        let scene_path = mesh_scene(
            &dir,
            &[("path", "\"models/torus.obj\""), ("material", "\"red\"")],
        );
        let scene = load_ok(&scene_path);
        let names: Vec<_> = scene.materials.iter().map(|m| m.name.as_str()).collect();
        assert_eq!(names, ["blue", "red"], "no MTL materials are added");
        let red = scene
            .materials
            .iter()
            .position(|m| m.name == "red")
            .unwrap() as u32;
        let mesh = &scene.triangles[1..];
        assert_eq!(mesh.len(), 48 * 24 * 2);
        assert!(mesh.iter().all(|t| t.material == red));

        // With an override the MTL file is never read: a missing one is fine.
        dir.write(
            "models/nomtl.obj",
            &format!("mtllib missing.mtl\nusemtl nothing\n{ONE_TRIANGLE_OBJ}"),
        );
        let scene_path = mesh_scene(
            &dir,
            &[("path", "\"models/nomtl.obj\""), ("material", "\"blue\"")],
        );
        assert_eq!(load_ok(&scene_path).triangles.len(), 2);
    }

    #[test]
    fn without_an_override_faces_use_their_mtl_materials() {
        let dir = TempDir::new("mtl");
        let obj = copy_torus(&dir, "models");
        let scene = load_ok(&mesh_scene(&dir, &[("path", "\"models/torus.obj\"")]));

        let find = |name: &str| scene.materials.iter().position(|m| m.name == name);
        let gold = find("torus.obj:gold").expect("MTL materials are named file.obj:name");
        let teal = find("torus.obj:teal").unwrap();
        assert_eq!(scene.materials.len(), 4);
        assert_eq!(
            scene.materials[gold],
            Material {
                name: "torus.obj:gold".into(),
                ambient: DVec3::new(0.10, 0.08, 0.02),
                diffuse: DVec3::new(0.75, 0.58, 0.16),
                specular: DVec3::new(0.60, 0.55, 0.40),
                shininess: 128.0,
                reflection: 0.0,
            }
        );
        assert_eq!(
            scene.materials[teal],
            Material {
                name: "torus.obj:teal".into(),
                ambient: DVec3::new(0.02, 0.08, 0.08),
                diffuse: DVec3::new(0.08, 0.50, 0.50),
                specular: DVec3::new(0.30, 0.30, 0.30),
                shininess: 64.0,
                reflection: 0.0,
            }
        );
        // Face for face, the same triangles and materials as the OBJ loader gives.
        let raw = load_obj(&obj, true).unwrap();
        let mesh = &scene.triangles[1..];
        assert_eq!(mesh.len(), raw.triangles.len());
        for (t, r) in mesh.iter().zip(&raw.triangles) {
            assert_eq!(Some(t.vertices), raw.vertices(r));
            let want = format!("torus.obj:{}", raw.materials[r.material().unwrap()].name);
            assert_eq!(scene.materials[t.material as usize].name, want);
        }
        let gold_faces = mesh.iter().filter(|t| t.material == gold as u32).count();
        assert_eq!(gold_faces * 2, mesh.len(), "rings alternate gold and teal");
    }

    #[test]
    fn a_missing_mtl_colour_is_black_and_reflection_is_zero() {
        let dir = TempDir::new("black");
        dir.write("m.mtl", "newmtl only_kd\nKd 0.2 0.4 0.6\n");
        dir.write(
            "m.obj",
            &format!("mtllib m.mtl\nusemtl only_kd\n{ONE_TRIANGLE_OBJ}"),
        );
        let scene = load_ok(&mesh_scene(&dir, &[("path", "\"m.obj\"")]));
        let m = scene
            .materials
            .iter()
            .find(|m| m.name == "m.obj:only_kd")
            .unwrap();
        assert_eq!(m.ambient, DVec3::ZERO);
        assert_eq!(m.diffuse, DVec3::new(0.2, 0.4, 0.6));
        assert_eq!(m.specular, DVec3::ZERO);
        assert_eq!(m.shininess, 0.0);
        assert_eq!(m.reflection, 0.0);
    }

    #[test]
    fn obj_statements_and_index_forms() {
        let dir = TempDir::new("forms");
        // A quad written with every vertex form and negative indices,
        // plus a zero-area face (skipped silently inside an OBJ).
        dir.write(
            "m.obj",
            "# comment\no thing\ng group\ns off\n\
             v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n\
             f 1 2/1 3//1 4/1/1\n\
             f -4 -3 -2 -1\n\
             f 1 2 2\n\
             f 1 2 1\n",
        );
        let scene = load_ok(&mesh_scene(
            &dir,
            &[("path", "\"m.obj\""), ("material", "\"red\"")],
        ));
        let mesh = &scene.triangles[1..];
        assert_eq!(
            mesh.len(),
            4,
            "two quads fan-triangulated; zero-area faces dropped"
        );
        let (a, b, c, d) = (DVec3::ZERO, DVec3::X, DVec3::new(1., 1., 0.), DVec3::Y);
        assert_eq!(mesh[0].vertices, [a, b, c]);
        assert_eq!(mesh[1].vertices, [a, c, d]);
        assert_eq!(mesh[2].vertices, [a, b, c]);
        assert_eq!(mesh[3].vertices, [a, c, d]);
    }

    #[test]
    fn an_obj_that_cannot_be_read_names_the_obj_and_the_mesh_entry() {
        let dir = TempDir::new("noobj");
        let doc = base().set("meshes[0].path", "\"models/nope.obj\"");
        for (name, text) in [("scene.toml", doc.toml()), ("scene.json", doc.json())] {
            let scene_path = dir.write(name, &text.text);
            let e = load_err(&scene_path);
            let line = text.line("meshes[0].path");
            let at = format!("{}:{line}", scene_path.display());
            assert_error(
                &e,
                &dir.join("models/nope.obj"),
                None,
                None,
                &["cannot read OBJ file", "meshes[0].path", &at],
            );
        }
        // The same for a folder where the file should be.
        std::fs::create_dir_all(dir.join("models/folder.obj")).unwrap();
        let scene_path = mesh_scene(&dir, &[("path", "\"models/folder.obj\"")]);
        let e = load_err(&scene_path);
        assert_error(
            &e,
            &dir.join("models/folder.obj"),
            None,
            None,
            &["cannot read OBJ file"],
        );
    }

    #[test]
    fn a_bad_obj_line_names_the_obj_line_and_statement() {
        let dir = TempDir::new("badobj");
        let cases: &[(&str, usize, &str)] = &[
            ("v 0 0 0\nv 1 2\n", 2, "v"),
            ("v 0 0 0\nv 1 0 nan\n", 2, "v"),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n", 5, "f"),
            ("v 0 0 0\nf 0 1 1\n", 2, "f"),
        ];
        for &(text, line, key) in cases {
            let obj = dir.write("m.obj", text);
            let scene_path = mesh_scene(&dir, &[("path", "\"m.obj\""), ("material", "\"red\"")]);
            let e = load_err(&scene_path);
            assert_error(&e, &obj, Some(line), Some(key), &[]);
        }
    }

    #[test]
    fn a_face_without_material_is_an_error_unless_overridden() {
        let dir = TempDir::new("nomat");
        dir.write("m.mtl", "newmtl a\nKd 1 0 0\n");
        // (OBJ text, line, statement, words)
        let cases: &[(&str, usize, &str, &[&str])] = &[
            // No usemtl before the face: at the face.
            (
                "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
                5,
                "usemtl",
                &["no material"],
            ),
            // No mtllib/usemtl at all.
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
                4,
                "usemtl",
                &["no material"],
            ),
            // A usemtl naming a material the MTL does not define: at the usemtl.
            (
                "mtllib m.mtl\nusemtl b\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
                2,
                "usemtl",
                &["'b'", "not defined"],
            ),
            // An MTL file that is not there: at the mtllib.
            (
                "mtllib gone.mtl\nusemtl a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
                1,
                "mtllib",
                &["cannot read mtl file", "gone.mtl"],
            ),
        ];
        for &(text, line, key, words) in cases {
            let obj = dir.write("m.obj", text);
            let scene_path = mesh_scene(&dir, &[("path", "\"m.obj\"")]);
            assert_error(&load_err(&scene_path), &obj, Some(line), Some(key), words);
            // With a `material` override the same OBJ is fine.
            let scene_path = mesh_scene(&dir, &[("path", "\"m.obj\""), ("material", "\"red\"")]);
            assert_eq!(load_ok(&scene_path).triangles.len(), 2);
        }
    }

    #[test]
    fn negative_mtl_colours_are_errors() {
        let dir = TempDir::new("negmtl");
        dir.write("m.mtl", "newmtl dark\nKd 0.5 0.5 0.5\nKs 0.1 -0.2 0.1\n");
        dir.write(
            "m.obj",
            &format!("mtllib m.mtl\nusemtl dark\n{ONE_TRIANGLE_OBJ}"),
        );
        let doc = base().set("meshes[0].path", "\"m.obj\"");
        let text = doc.toml();
        let scene_path = dir.write("scene.toml", &text.text);
        let e = load_err(&scene_path);
        let line = Some(text.line("meshes[0].path"));
        let words = ["\"dark\"", "Ks", ">= 0"];
        assert_error(&e, &scene_path, line, Some("meshes[0].path"), &words);
        // Unused by the override, the MTL does not matter.
        let doc = doc.set("meshes[0].material", "\"red\"");
        assert_eq!(
            load_ok(&dir.write("scene.toml", &doc.toml().text))
                .triangles
                .len(),
            2
        );
    }

    #[test]
    fn mtl_errors_name_the_mtl_file() {
        let dir = TempDir::new("badmtl");
        let mtl = dir.write("m.mtl", "newmtl a\nKd 1 0\n");
        dir.write(
            "m.obj",
            &format!("mtllib m.mtl\nusemtl a\n{ONE_TRIANGLE_OBJ}"),
        );
        let e = load_err(&mesh_scene(&dir, &[("path", "\"m.obj\"")]));
        assert_error(&e, &mtl, Some(2), Some("Kd"), &["expected 3 numbers"]);
    }

    #[test]
    fn the_same_obj_twice_gives_two_copies() {
        let dir = TempDir::new("twice");
        copy_torus(&dir, "models");
        let doc = base()
            .set("meshes[0].path", "\"models/torus.obj\"")
            .set("meshes[1].path", "\"models/torus.obj\"")
            .set("meshes[1].translate", "[3, 0, 0]");
        let scene = load_ok(&dir.write("scene.toml", &doc.toml().text));
        let n = 48 * 24 * 2;
        assert_eq!(scene.triangles.len(), 1 + 2 * n);
        for (a, b) in scene.triangles[1..=n].iter().zip(&scene.triangles[n + 1..]) {
            for (va, vb) in a.vertices.iter().zip(b.vertices) {
                assert_close(vb, *va + DVec3::new(3.0, 0.0, 0.0));
            }
        }
    }
}

// ============================================================== complete examples

mod examples {
    use super::*;

    /// The example of the contract, with the shipped torus as its mesh.
    const EXAMPLE_TOML: &str = r#"
[camera]
position = [0.0, 0.0, 1.0]      # eye point, the origin of every primary ray
look_at  = [0.0, 0.0, 0.0]
up       = [0.0, 1.0, 0.0]
vfov     = 58.7155

[render]
width         = 1920
height        = 1080
min_intensity = 0.05
max_depth     = 10
background    = [0.0, 0.0, 0.0]
shadow_mode   = "ambient"
samples       = 1

[[lights]]
position = [5.0, 5.0, 5.0]
ambient  = [1.0, 1.0, 1.0]
diffuse  = [1.0, 1.0, 1.0]
specular = [1.0, 1.0, 1.0]

[materials.red]
ambient    = [0.1, 0.0, 0.0]
diffuse    = [0.7, 0.0, 0.0]
specular   = [1.0, 1.0, 1.0]
shininess  = 100.0
reflection = 0.5

[[spheres]]
center   = [-0.2, 0.0, -1.0]
radius   = 0.7
material = "red"

[[triangles]]
vertices = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
material = "red"

[[meshes]]
path      = "models/torus.obj"
material  = "red"
scale     = 1.0
rotate    = [0.0, 0.0, 0.0]
translate = [0.0, 0.0, 0.0]
"#;

    const EXAMPLE_JSON: &str = r#"{
  "camera": {
    "position": [0.0, 0.0, 1.0],
    "look_at": [0.0, 0.0, 0.0],
    "up": [0.0, 1.0, 0.0],
    "vfov": 58.7155
  },
  "render": {
    "width": 1920, "height": 1080, "min_intensity": 0.05, "max_depth": 10,
    "background": [0.0, 0.0, 0.0], "shadow_mode": "ambient", "samples": 1
  },
  "lights": [
    {"position": [5.0, 5.0, 5.0], "ambient": [1.0, 1.0, 1.0],
     "diffuse": [1.0, 1.0, 1.0], "specular": [1.0, 1.0, 1.0]}
  ],
  "materials": {
    "red": {"ambient": [0.1, 0.0, 0.0], "diffuse": [0.7, 0.0, 0.0],
            "specular": [1.0, 1.0, 1.0], "shininess": 100.0, "reflection": 0.5}
  },
  "spheres": [{"center": [-0.2, 0.0, -1.0], "radius": 0.7, "material": "red"}],
  "triangles": [
    {"vertices": [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], "material": "red"}
  ],
  "meshes": [
    {"path": "models/torus.obj", "material": "red", "scale": 1.0,
     "rotate": [0.0, 0.0, 0.0], "translate": [0.0, 0.0, 0.0]}
  ]
}"#;

    #[test]
    fn the_contract_example_has_every_value() {
        let dir = TempDir::new("example");
        let obj = copy_torus(&dir, "models");
        let scene = load_ok(&dir.write("example.toml", EXAMPLE_TOML));

        assert_eq!(
            scene.camera,
            Camera {
                position: DVec3::new(0.0, 0.0, 1.0),
                look_at: DVec3::ZERO,
                up: DVec3::Y,
                vfov_degrees: 58.7155,
            }
        );
        assert_eq!(
            scene.render,
            RenderSettings {
                width: 1920,
                height: 1080,
                min_intensity: 0.05,
                max_depth: 10,
                background: DVec3::ZERO,
                shadow_mode: ShadowMode::Ambient,
                samples: 1,
            }
        );
        assert_eq!(
            scene.lights,
            vec![Light {
                position: DVec3::splat(5.0),
                ambient: DVec3::ONE,
                diffuse: DVec3::ONE,
                specular: DVec3::ONE,
            }]
        );
        assert_eq!(
            scene.materials,
            vec![Material {
                name: "red".into(),
                ambient: DVec3::new(0.1, 0.0, 0.0),
                diffuse: DVec3::new(0.7, 0.0, 0.0),
                specular: DVec3::ONE,
                shininess: 100.0,
                reflection: 0.5,
            }]
        );
        assert_eq!(
            scene.spheres,
            vec![Sphere {
                center: DVec3::new(-0.2, 0.0, -1.0),
                radius: 0.7,
                material: 0,
            }]
        );
        assert_eq!(
            scene.triangles[0],
            Triangle::flat([DVec3::ZERO, DVec3::X, DVec3::Y], 0)
        );
        // The mesh, untransformed, all red.
        let raw = load_obj(&obj, false).unwrap();
        assert_eq!(scene.triangles.len(), 1 + raw.triangles.len());
        for (t, r) in scene.triangles[1..].iter().zip(&raw.triangles) {
            assert_eq!(Some(t.vertices), raw.vertices(r));
            assert_eq!(t.material, 0);
        }
        assert_eq!(scene.object_count(), 2 + raw.triangles.len());
    }

    #[test]
    fn the_contract_example_in_json_is_the_same_scene() {
        let dir = TempDir::new("example-json");
        copy_torus(&dir, "models");
        let toml = load_ok(&dir.write("example.toml", EXAMPLE_TOML));
        let json = load_ok(&dir.write("example.json", EXAMPLE_JSON));
        assert_eq!(toml, json);
    }

    #[test]
    fn a_scene_with_every_kind_of_entry_is_the_same_in_toml_and_json() {
        let dir = TempDir::new("same");
        copy_torus(&dir, "models");
        dir.write("models/tri.obj", ONE_TRIANGLE_OBJ);
        let doc = two_triangles()
            .set("camera.up", "[0, 1, 0.5]")
            .set("camera.vfov", "45")
            .set("render.width", "320")
            .set("render.height", "240")
            .set("render.min_intensity", "0.01")
            .set("render.max_depth", "5")
            .set("render.background", "[0.2, 0.3, 0.4]")
            .set("render.shadow_mode", "\"seed\"")
            .set("render.samples", "4")
            .set("lights[0].ambient", "[0.1, 0.1, 0.1]")
            .set("lights[1].position", "[-3, 2, 1]")
            .set("lights[1].specular", "[0.5, 0.5, 0.5]")
            .set("materials.red.specular", "[1, 1, 1]")
            .set("materials.red.shininess", "64")
            .set("materials.red.reflection", "0.25")
            .set("spheres[1].center", "[1, 1, -2]")
            .set("spheres[1].radius", "0.3")
            .set("spheres[1].material", "\"blue\"")
            .set("meshes[0].path", "\"models/torus.obj\"")
            .set("meshes[0].scale", "[0.5, 1, 2]")
            .set("meshes[0].rotate", "[10, 20, 30]")
            .set("meshes[0].translate", "[0, -1, -4]")
            .set("meshes[1].path", "\"models/tri.obj\"")
            .set("meshes[1].material", "\"red\"")
            .set("meshes[1].scale", "2");
        let toml = load_ok(&dir.write("scene.toml", &doc.toml().text));
        let json = load_ok(&dir.write("scene.json", &doc.json().text));
        assert_eq!(toml, json);
        assert_eq!(toml.lights.len(), 2);
        assert_eq!(toml.spheres.len(), 2);
        assert_eq!(toml.triangles.len(), 2 + 48 * 24 * 2 + 1);
        assert_eq!(toml.materials.len(), 4);
    }

    /// The first fenced block of `lang` after `heading` in docs/scene-format.md.
    fn docs_block(doc: &str, heading: &str, lang: &str) -> String {
        let after = &doc[doc
            .find(heading)
            .unwrap_or_else(|| panic!("no {heading:?} in the docs"))..];
        let fence = format!("```{lang}\n");
        let start = after
            .find(&fence)
            .unwrap_or_else(|| panic!("no {lang} block after {heading:?}"))
            + fence.len();
        let len = after[start..].find("```").unwrap();
        after[start..start + len].to_string()
    }

    #[test]
    fn the_complete_example_in_the_docs_parses_the_same_in_toml_and_json() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/scene-format.md");
        let doc = std::fs::read_to_string(&path).unwrap();
        let dir = TempDir::new("docs");
        copy_torus(&dir, "models");
        let toml = load_ok(&dir.write(
            "example.toml",
            &docs_block(&doc, "## Complete example", "toml"),
        ));
        let json = load_ok(&dir.write(
            "example.json",
            &docs_block(&doc, "## Complete example", "json"),
        ));
        assert_eq!(toml, json);
        assert!(!toml.spheres.is_empty() && toml.triangles.len() > 1);
        // The error line quoted in the docs is what the code prints.
        let bad = docs_block(&doc, "## Errors", "toml");
        let shown = parse_err(&bad, SceneFormat::Toml).to_string();
        assert!(
            doc.contains(&shown.replace(TOML_FILE, "scene.toml")),
            "the docs should quote: {shown}"
        );
    }
}

// ============================================================== mesh files: bad input, glTF, normals

/// The folder of the small glTF models (written by tests/models/make_models.py).
fn test_models_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/models")
}

/// Copies `name` from tests/models into `dir`; returns its path there.
fn copy_model(dir: &TempDir, name: &str) -> PathBuf {
    let to = dir.join(name);
    std::fs::copy(test_models_dir().join(name), &to).unwrap();
    to
}

/// Writes `scene.toml` in `dir`: the base scene plus one `[[meshes]]` entry
/// with the given keys (values as TOML text). Returns the path and the line
/// of `meshes[0].path`.
fn scene_with_mesh(dir: &TempDir, keys: &[(&str, &str)]) -> (PathBuf, usize) {
    let mut doc = base();
    for (key, value) in keys {
        doc = doc.set(&format!("meshes[0].{key}"), value);
    }
    let text = doc.toml();
    let line = text.line("meshes[0].path");
    (dir.write("scene.toml", &text.text), line)
}

mod bad_mesh_files {
    use super::*;

    /// Loads a scene whose mesh is `name` (already in `dir`), material
    /// overridden, and returns its error and the `(from ...)` note a file
    /// error without a line ends with.
    fn error_of(dir: &TempDir, name: &str) -> (SceneError, String) {
        let (scene, line) = scene_with_mesh(
            dir,
            &[("path", &format!("\"{name}\"")), ("material", "\"red\"")],
        );
        let note = format!(" (from meshes[0].path in {}:{line})", scene.display());
        (load_err(&scene), note)
    }

    #[track_caller]
    fn assert_file_error(dir: &TempDir, name: &str, message: &str) {
        let (e, note) = error_of(dir, name);
        let want = format!("{}: {message}{note}", dir.join(name).display());
        assert_eq!(e.to_string(), want);
        assert_eq!((e.line, e.key.as_deref()), (None, None));
    }

    #[test]
    fn an_obj_without_faces_is_an_error() {
        let dir = TempDir::new("nofaces");
        dir.write("empty.obj", "");
        dir.write("points.obj", "# only vertices\nv 0 0 0\nv 1 0 0\nv 0 1 0\n");
        let no_faces = "no faces: the file has no `f` statement, so the mesh would draw nothing";
        assert_file_error(&dir, "empty.obj", no_faces);
        assert_file_error(&dir, "points.obj", no_faces);
        dir.write("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\nf 1 1 2\n");
        assert_file_error(
            &dir,
            "flat.obj",
            "all 2 faces have zero area, so the mesh would draw nothing",
        );
    }

    #[test]
    fn a_binary_file_read_as_obj_names_the_line_of_the_first_bad_byte() {
        let dir = TempDir::new("binobj");
        // Bytes 0..=255: a newline at 10, the first invalid UTF-8 byte at 128.
        let bytes: Vec<u8> = (0..=255).collect();
        std::fs::write(dir.join("binary.obj"), &bytes).unwrap();
        let (e, _) = error_of(&dir, "binary.obj");
        assert_eq!(
            e.to_string(),
            format!(
                "{}:2: not a text OBJ file: invalid UTF-8 at byte 128 (a binary file? kdray reads binary glTF as .glb)",
                dir.join("binary.obj").display()
            )
        );
        // The glTF binary itself, misnamed .obj: the same error, not an empty mesh.
        std::fs::copy(test_models_dir().join("tetra.glb"), dir.join("tetra.obj")).unwrap();
        let (e, _) = error_of(&dir, "tetra.obj");
        assert!(e.message.starts_with("not a text OBJ file"), "{e}");
    }

    #[test]
    fn unknown_extensions_are_errors() {
        let dir = TempDir::new("ext");
        dir.write("model.stl", "solid x\nendsolid x\n");
        dir.write("model", ONE_TRIANGLE_OBJ);
        assert_file_error(
            &dir,
            "model.stl",
            "unknown mesh file extension \".stl\"; kdray reads .obj, .gltf and .glb",
        );
        assert_file_error(
            &dir,
            "model",
            "no mesh file extension; kdray reads .obj, .gltf and .glb",
        );
        // Extensions are case-insensitive.
        dir.write("UPPER.OBJ", ONE_TRIANGLE_OBJ);
        let (scene, _) =
            scene_with_mesh(&dir, &[("path", "\"UPPER.OBJ\""), ("material", "\"red\"")]);
        assert_eq!(load_ok(&scene).triangles.len(), 2);
    }

    #[test]
    fn truncated_and_corrupt_gltf_files_are_errors() {
        let dir = TempDir::new("badgltf");
        let glb = std::fs::read(test_models_dir().join("tetra.glb")).unwrap();
        std::fs::write(dir.join("cut.glb"), &glb[..500]).unwrap();
        assert_file_error(
            &dir,
            "cut.glb",
            &format!(
                "truncated GLB: its header declares {} bytes, the file has 500",
                glb.len()
            ),
        );
        std::fs::write(dir.join("header.glb"), &glb[..10]).unwrap();
        assert_file_error(
            &dir,
            "header.glb",
            "truncated GLB: 10 bytes, less than its 12-byte header",
        );
        let mut lying = glb.clone();
        lying[8..12].copy_from_slice(&4u32.to_le_bytes());
        std::fs::write(dir.join("lying.glb"), &lying).unwrap();
        assert_file_error(
            &dir,
            "lying.glb",
            "corrupt GLB: its header declares 4 bytes, less than the 12-byte header",
        );
        // Not JSON, and JSON that is not glTF: the crate's reason follows.
        dir.write("text.gltf", "{ not json");
        dir.write("empty.glb", "");
        dir.write(
            "other.gltf",
            "{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [{\"mesh\": 3}]}",
        );
        for name in ["text.gltf", "empty.glb", "other.gltf"] {
            let (e, note) = error_of(&dir, name);
            assert_eq!(e.file, dir.join(name));
            assert!(e.message.starts_with("not a valid glTF 2.0 file: "), "{e}");
            assert!(e.message.ends_with(&note), "{e}");
            assert!(
                std::error::Error::source(&e).is_some(),
                "{e} keeps the crate's error"
            );
        }
        let (e, _) = error_of(&dir, "other.gltf");
        assert!(
            e.message.contains("nodes[0].mesh"),
            "names the JSON path: {e}"
        );
        // Valid glTF with no scene, or a scene with no mesh: nothing to draw.
        dir.write("noscene.gltf", "{\"asset\": {\"version\": \"2.0\"}}");
        assert_file_error(
            &dir,
            "noscene.gltf",
            "no scene: the file defines no scene to place its meshes, so it would draw nothing",
        );
        dir.write(
            "nomesh.gltf",
            "{\"asset\": {\"version\": \"2.0\"}, \"scenes\": [{\"nodes\": [0]}], \"nodes\": [{}]}",
        );
        assert_file_error(
            &dir,
            "nomesh.gltf",
            "no triangles: the scene's nodes place no mesh with triangles, so it would draw nothing",
        );
    }

    /// tetra_external.gltf in `dir` with its buffer URI replaced by `uri`.
    fn with_buffer_uri(dir: &TempDir, name: &str, uri: &str) {
        let text = std::fs::read_to_string(test_models_dir().join("tetra_external.gltf")).unwrap();
        let mut json: serde_json::Value = serde_json::from_str(&text).unwrap();
        json["buffers"][0]["uri"] = serde_json::Value::String(uri.to_string());
        dir.write(name, &json.to_string());
    }

    #[test]
    fn buffer_uris_outside_readable_files_are_errors() {
        let dir = TempDir::new("uris");
        with_buffer_uri(&dir, "missing.gltf", "nowhere.bin");
        let (e, note) = error_of(&dir, "missing.gltf");
        let prefix = format!(
            "buffer 0: cannot read {} (URI \"nowhere.bin\"): ",
            dir.join("nowhere.bin").display()
        );
        assert!(
            e.message.starts_with(&prefix) && e.message.ends_with(&note),
            "{e}"
        );
        with_buffer_uri(&dir, "device.gltf", "/dev/zero");
        assert_file_error(
            &dir,
            "device.gltf",
            "buffer 0: cannot read /dev/zero (URI \"/dev/zero\"): not a regular file",
        );
        with_buffer_uri(&dir, "url.gltf", "https://example.com/tetra.bin");
        assert_file_error(
            &dir,
            "url.gltf",
            "buffer 0: URI \"https://example.com/tetra.bin\": a \"https:\" URI; kdray reads buffers only from files named by a relative path, or from data: URIs",
        );
        with_buffer_uri(&dir, "folder.gltf", ".");
        let (e, _) = error_of(&dir, "folder.gltf");
        assert!(e.message.contains("not a regular file"), "{e}");
        // A buffer file shorter than its byteLength.
        with_buffer_uri(&dir, "short.gltf", "short.bin");
        let bin = std::fs::read(test_models_dir().join("tetra.bin")).unwrap();
        std::fs::write(dir.join("short.bin"), &bin[..100]).unwrap();
        assert_file_error(
            &dir,
            "short.gltf",
            "buffer 0 is truncated: byteLength 120 but 100 bytes present",
        );
        // A bad data URI.
        with_buffer_uri(
            &dir,
            "data.gltf",
            "data:application/octet-stream;base64,AA#A",
        );
        let (e, _) = error_of(&dir, "data.gltf");
        assert!(
            e.message.contains("invalid base64 character at offset 2"),
            "{e}"
        );
    }

    #[test]
    fn points_and_lines_are_errors() {
        let dir = TempDir::new("lines");
        copy_model(&dir, "lines.gltf");
        assert_file_error(
            &dir,
            "lines.gltf",
            "mesh 0 primitive 0: mode Lines is not a surface; kdray draws TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN only",
        );
    }
}

mod gltf_meshes {
    use super::*;
    use glam::{DMat3, DMat4, DQuat};

    // The tetrahedron of tests/models/make_models.py, as written there.
    const TETRA_POSITIONS: [[f32; 3]; 4] = [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]];
    const TETRA_NORMALS: [[f32; 3]; 4] = [
        [-0.57735026, -0.57735026, -0.57735026],
        [1., 0., 0.],
        [0., 1., 0.],
        [0., 0., 1.],
    ];
    const TETRA_TRIANGLES: [[usize; 3]; 4] = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
    const TETRA_TRANSLATION: [f32; 3] = [1.0, 2.0, 3.0];
    const TETRA_ROTATION: [f32; 4] = [0.0, 0.38268343, 0.0, 0.923_879_5];
    const TETRA_SCALE: [f32; 3] = [2.0, 1.0, 0.5];

    /// The tetrahedron's node transform (root T * R, child S), in f64.
    fn node_matrix() -> DMat4 {
        let v = |a: [f32; 3]| DVec3::from_array(a.map(f64::from));
        let [x, y, z, w] = TETRA_ROTATION.map(f64::from);
        DMat4::from_translation(v(TETRA_TRANSLATION))
            * DMat4::from_quat(DQuat::from_xyzw(x, y, z, w))
            * DMat4::from_scale(v(TETRA_SCALE))
    }

    /// The tetrahedron placed by its nodes, as an OBJ with `v//vn` faces.
    fn tetra_obj() -> String {
        let m = node_matrix();
        let n = DMat3::from_mat4(m).inverse().transpose();
        let mut text = String::new();
        for p in TETRA_POSITIONS {
            let p = m.transform_point3(DVec3::from_array(p.map(f64::from)));
            text.push_str(&format!("v {:?} {:?} {:?}\n", p.x, p.y, p.z));
        }
        for normal in TETRA_NORMALS {
            let v = n * DVec3::from_array(normal.map(f64::from));
            text.push_str(&format!("vn {:?} {:?} {:?}\n", v.x, v.y, v.z));
        }
        for t in TETRA_TRIANGLES {
            let [a, b, c] = t.map(|i| i + 1);
            text.push_str(&format!("f {a}//{a} {b}//{b} {c}//{c}\n"));
        }
        text
    }

    /// The mesh triangles of a scene whose one mesh entry is `name` in `dir`,
    /// with `keys` added.
    fn mesh_triangles(dir: &TempDir, name: &str, keys: &[(&str, &str)]) -> Scene {
        let path = format!("\"{name}\"");
        let mut all = vec![("path", path.as_str())];
        all.extend_from_slice(keys);
        let (scene, _) = scene_with_mesh(dir, &all);
        load_ok(&scene)
    }

    const ENTRY: [(&str, &str); 4] = [
        ("material", "\"red\""),
        ("scale", "1.5"),
        ("rotate", "[10, 20, 30]"),
        ("translate", "[0.5, 0, -1]"),
    ];

    #[test]
    fn obj_and_glb_under_a_node_hierarchy_give_the_same_triangles_and_normals() {
        let dir = TempDir::new("glb-vs-obj");
        copy_model(&dir, "tetra.glb");
        dir.write("tetra.obj", &tetra_obj());
        let from_glb = mesh_triangles(&dir, "tetra.glb", &ENTRY);
        let from_obj = mesh_triangles(&dir, "tetra.obj", &ENTRY);
        // triangles[0] is the base scene's own triangle.
        assert_eq!(from_glb.triangles.len(), 1 + 4);
        assert_eq!(from_obj.triangles.len(), 1 + 4);
        for (g, o) in from_glb.triangles[1..].iter().zip(&from_obj.triangles[1..]) {
            for k in 0..3 {
                // glTF positions and node transforms are f32.
                let d = (g.vertices[k] - o.vertices[k]).abs().max_element();
                assert!(d < 1e-5, "{:?} vs {:?}", g.vertices, o.vertices);
                let (gn, on) = (
                    from_glb.normals_of(g).unwrap()[k],
                    from_obj.normals_of(o).unwrap()[k],
                );
                assert!((gn - on).abs().max_element() < 1e-5, "{gn} vs {on}");
                assert!((gn.length() - 1.0).abs() < 1e-12);
            }
            assert_eq!(g.material, o.material);
        }
        // The transforms really moved it: the node translation alone is 1..3 away.
        let centre = from_glb.triangles[1..]
            .iter()
            .flat_map(|t| t.vertices)
            .sum::<DVec3>()
            / 12.0;
        assert!(centre.length() > 2.0, "{centre}");
    }

    #[test]
    fn embedded_external_and_binary_buffers_give_one_mesh() {
        let dir = TempDir::new("buffers");
        for name in [
            "tetra.glb",
            "tetra_embedded.gltf",
            "tetra_external.gltf",
            "tetra.bin",
        ] {
            copy_model(&dir, name);
        }
        let glb = mesh_triangles(&dir, "tetra.glb", &ENTRY);
        assert_eq!(mesh_triangles(&dir, "tetra_embedded.gltf", &ENTRY), glb);
        assert_eq!(mesh_triangles(&dir, "tetra_external.gltf", &ENTRY), glb);
        // The loader reports the buffer file among the files it read.
        let (scene, _) = scene_with_mesh(&dir, &[("path", "\"tetra_external.gltf\"")]);
        let mut read = Vec::new();
        kdray::scene::load_scene_observed(&scene, &mut |p| read.push(p.to_path_buf())).unwrap();
        assert_eq!(
            read,
            [
                scene.clone(),
                dir.join("tetra_external.gltf"),
                dir.join("tetra.bin")
            ]
        );
    }

    #[test]
    fn pbr_materials_follow_the_documented_rule() {
        let dir = TempDir::new("pbr");
        copy_model(&dir, "tetra.glb");
        copy_model(&dir, "plain.gltf");
        let scene = mesh_triangles(&dir, "tetra.glb", &[]);
        let gold = scene
            .materials
            .iter()
            .position(|m| m.name == "tetra.glb:gold")
            .unwrap();
        let m = &scene.materials[gold];
        // baseColorFactor (1, 0.75, 0.25), metallic 1, roughness 0.5.
        let base = DVec3::new(1.0, 0.75, 0.25);
        assert_eq!(m.diffuse, base);
        assert_close(m.ambient, 0.1 * base);
        assert_eq!(m.specular, DVec3::splat(0.5));
        assert_eq!(m.reflection, 0.5, "metallic x (1 - roughness)");
        let alpha = 0.5f64 * 0.5;
        assert!((m.shininess - 4.0 * (2.0 / (alpha * alpha) - 2.0)).abs() < 1e-9);
        assert!(scene.triangles[1..]
            .iter()
            .all(|t| t.material == gold as u32));
        // No material: glTF's default (white, metallic 1, roughness 1) is a
        // rough white surface, not a mirror.
        let scene = mesh_triangles(&dir, "plain.gltf", &[]);
        let m = scene.materials.last().unwrap();
        assert_eq!(m.name, "plain.gltf:default");
        assert_eq!((m.diffuse, m.specular), (DVec3::ONE, DVec3::ZERO));
        assert_close(m.ambient, DVec3::splat(0.1));
        assert_eq!((m.shininess, m.reflection), (0.0, 0.0));
        // A `material` key replaces them all, and no glTF material is added.
        let scene = mesh_triangles(&dir, "tetra.glb", &[("material", "\"blue\"")]);
        assert_eq!(scene.materials.len(), 2);
        assert!(scene.triangles[1..]
            .iter()
            .all(|t| scene.materials[t.material as usize].name == "blue"));
    }

    #[test]
    fn a_non_indexed_primitive_without_normals_is_flat() {
        let dir = TempDir::new("plain");
        copy_model(&dir, "plain.gltf");
        let scene = mesh_triangles(&dir, "plain.gltf", &[("material", "\"red\"")]);
        assert_eq!(scene.triangles.len(), 2);
        let node = node_matrix();
        let want = [0, 1, 2]
            .map(|i| node.transform_point3(DVec3::from_array(TETRA_POSITIONS[i].map(f64::from))));
        for (g, w) in scene.triangles[1].vertices.iter().zip(want) {
            assert!((*g - w).abs().max_element() < 1e-5, "{g} vs {w}");
        }
        assert_eq!(scene.normals_of(&scene.triangles[1]), None);
        // smooth = true: no vertex is shared, so every corner gets the face's normal.
        let scene = mesh_triangles(
            &dir,
            "plain.gltf",
            &[("material", "\"red\""), ("smooth", "true")],
        );
        let [a, b, c] = scene.triangles[1].vertices;
        let face = (b - a).cross(c - a).normalize();
        for n in scene.normals_of(&scene.triangles[1]).unwrap() {
            assert!((n - face).abs().max_element() < 1e-12, "{n} vs {face}");
        }
    }
}

mod mesh_normals {
    use super::*;

    /// A mesh's triangle as loaded, its normals looked up in the scene.
    #[derive(Debug, Clone, Copy)]
    struct Shaded {
        vertices: [DVec3; 3],
        normals: Option<[DVec3; 3]>,
    }

    fn load(dir: &TempDir, obj: &str, keys: &[(&str, &str)]) -> Vec<Shaded> {
        dir.write("m.obj", obj);
        let mut all = vec![("path", "\"m.obj\""), ("material", "\"red\"")];
        all.extend_from_slice(keys);
        let (scene, _) = scene_with_mesh(dir, &all);
        let scene = load_ok(&scene);
        scene.triangles[1..]
            .iter()
            .map(|t| Shaded {
                vertices: t.vertices,
                normals: scene.normals_of(t),
            })
            .collect()
    }

    const WITH_NORMALS: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 2\nvn 0 1 1\nvn 1 0 0\n\
                                f 1//1 2//2 3//3\nf 1/1/1 3/1/2 2/1/3\n";

    #[test]
    fn obj_normals_are_kept_per_corner_and_normalised() {
        let dir = TempDir::new("vn");
        let t = load(&dir, WITH_NORMALS, &[]);
        let s = 0.5f64.sqrt();
        // Corners in face order; both faces give normals 1, 2, 3 in that order.
        for t in &t[..2] {
            let want = [DVec3::Z, DVec3::new(0.0, s, s), DVec3::X];
            for (got, want) in t.normals.unwrap().into_iter().zip(want) {
                assert_close(got, want);
            }
        }
    }

    #[test]
    fn smooth_false_is_flat_and_a_file_without_normals_is_flat_by_default() {
        let dir = TempDir::new("flat");
        assert!(load(&dir, WITH_NORMALS, &[("smooth", "false")])
            .iter()
            .all(|t| t.normals.is_none()));
        assert!(load(&dir, ONE_TRIANGLE_OBJ, &[])
            .iter()
            .all(|t| t.normals.is_none()));
        // A face with normals on only some corners is flat by default.
        let partial = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2 3\n";
        assert_eq!(load(&dir, partial, &[])[0].normals, None);
        // With smooth = true the missing corners are computed (one face: its normal).
        assert_eq!(
            load(&dir, partial, &[("smooth", "true")])[0].normals,
            Some([DVec3::Z; 3])
        );
    }

    /// The unit cube [0, 1]^3 as an OBJ of 12 outward-wound triangles sharing 8 vertices.
    const CUBE: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n\
                        f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";

    #[test]
    fn smooth_true_computes_angle_weighted_normals_of_shared_vertices() {
        let dir = TempDir::new("cube");
        let triangles = load(&dir, CUBE, &[("smooth", "true")]);
        assert_eq!(triangles.len(), 12);
        for t in &triangles {
            for (v, n) in t.vertices.iter().zip(t.normals.unwrap()) {
                // Each corner's three faces meet at right angles: the diagonal.
                let want = (*v - DVec3::splat(0.5)).normalize();
                assert_close(n, want);
            }
        }
    }

    #[test]
    fn normals_follow_the_entry_transform_by_the_inverse_transpose() {
        let dir = TempDir::new("xform-n");
        // A plane x = z (normal (1, 0, -1)) stretched by 2 along x is the plane
        // x = 2z, whose normal is (1, 0, -2); then rotated 90 degrees about z.
        let obj = "v 0 0 0\nv 1 0 1\nv 0 1 0\nvn 1 0 -1\nf 1//1 2//1 3//1\n";
        let t = load(
            &dir,
            obj,
            &[("scale", "[2, 1, 1]"), ("rotate", "[0, 0, 90]")],
        );
        let want = DVec3::new(0.0, 1.0, -2.0) / 5f64.sqrt();
        for n in t[0].normals.unwrap() {
            assert_close(n, want);
        }
        // The normal is perpendicular to the transformed triangle.
        let [a, b, c] = t[0].vertices;
        assert!((b - a).dot(want).abs() < 1e-12 && (c - a).dot(want).abs() < 1e-12);
        // Computed normals are computed on the transformed mesh.
        let smooth = load(&dir, CUBE, &[("smooth", "true"), ("scale", "[1, 1, 4]")]);
        for t in &smooth {
            for (v, n) in t.vertices.iter().zip(t.normals.unwrap()) {
                // Still a box, so still the diagonal (1, 1, 1) / sqrt(3), not
                // the unscaled cube's normal carried through the scale.
                let want = (*v - DVec3::new(0.5, 0.5, 2.0)).signum().normalize();
                assert_close(n, want);
            }
        }
    }

    #[test]
    fn bad_normal_statements_name_their_line() {
        let dir = TempDir::new("badvn");
        for (obj, line, key) in [
            ("vn 0 0\n", 1, "vn"),
            ("v 0 0 0\nvn 0 nan 1\n", 2, "vn"),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//1\n", 4, "f"),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//0 2//1 3//1\n",
                5,
                "f",
            ),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//x 2//1 3//1\n",
                5,
                "f",
            ),
        ] {
            let obj_path = dir.write("m.obj", obj);
            let (scene, _) =
                scene_with_mesh(&dir, &[("path", "\"m.obj\""), ("material", "\"red\"")]);
            assert_error(&load_err(&scene), &obj_path, Some(line), Some(key), &[]);
        }
        let e = parse_err(
            &with_mesh().set("meshes[0].smooth", "\"yes\"").toml().text,
            SceneFormat::Toml,
        );
        assert_eq!(e.key.as_deref(), Some("meshes[0].smooth"), "{e}");
    }
}
