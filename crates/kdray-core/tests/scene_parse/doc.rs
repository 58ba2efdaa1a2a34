//! [`Doc`]: a scene document written once and rendered as TOML or JSON,
//! one key per line, so that a test knows the line of every key in both.

use super::*;

/// A scene document written once and rendered as TOML or as JSON, one key per
/// line. Values are written in the syntax the two formats share: numbers,
/// `"strings"` and `[arrays]`.
#[derive(Clone, Default)]
pub(crate) struct Doc(Table);

#[derive(Clone, Default)]
pub(crate) struct Table(Vec<(String, Node)>);

#[derive(Clone)]
pub(crate) enum Node {
    Value(String),
    Table(Table),
    /// An array of tables: `[[name]]` in TOML.
    Array(Vec<Table>),
}

/// `spheres[2]` -> ("spheres", Some(2)); `camera` -> ("camera", None).
pub(crate) fn split_index(segment: &str) -> (&str, Option<usize>) {
    match segment.strip_suffix(']').and_then(|s| s.split_once('[')) {
        Some((name, index)) => (name, Some(index.parse().unwrap())),
        None => (segment, None),
    }
}

pub(crate) fn join(prefix: &str, key: &str) -> String {
    if prefix.is_empty() {
        key.to_string()
    } else {
        format!("{prefix}.{key}")
    }
}

impl Table {
    pub(crate) fn get_mut(&mut self, name: &str) -> Option<&mut Node> {
        self.0.iter_mut().find(|(k, _)| k == name).map(|(_, n)| n)
    }

    /// The table at `segment` (`name` or `name[i]`), made if missing.
    pub(crate) fn child(&mut self, segment: &str) -> &mut Table {
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
    /// The table that holds the key at `path`, and the key's name in it.
    fn parent_of<'p>(&mut self, path: &'p str) -> (&mut Table, &'p str) {
        let (parents, last) = match path.rsplit_once('.') {
            Some((parents, last)) => (Some(parents), last),
            None => (None, path),
        };
        let mut table = &mut self.0;
        for segment in parents.into_iter().flat_map(|p| p.split('.')) {
            table = table.child(segment);
        }
        (table, last)
    }

    /// Sets the key at `path` (`camera.vfov`, `spheres[1].radius`,
    /// `materials.red.diffuse`) to `value`, replacing whatever was there.
    pub(crate) fn set(mut self, path: &str, value: &str) -> Self {
        let (table, last) = self.parent_of(path);
        let node = Node::Value(value.to_string());
        match table.get_mut(last) {
            Some(old) => *old = node,
            None => table.0.push((last.to_string(), node)),
        }
        self
    }

    /// Removes the key at `path`.
    pub(crate) fn remove(mut self, path: &str) -> Self {
        let (table, last) = self.parent_of(path);
        table.0.retain(|(k, _)| k != last);
        self
    }

    pub(crate) fn toml(&self) -> Text {
        let mut w = Writer::new(SceneFormat::Toml);
        toml_table(&mut w, "", "", &self.0);
        w.finish()
    }

    pub(crate) fn json(&self) -> Text {
        let mut w = Writer::new(SceneFormat::Json);
        w.plain("{".into());
        json_members(&mut w, "", &self.0, 1);
        w.plain("}".into());
        w.finish()
    }

    pub(crate) fn both(&self) -> [Text; 2] {
        [self.toml(), self.json()]
    }
}

/// A rendered [`Doc`], with the line of every key path.
pub(crate) struct Text {
    pub(crate) text: String,
    format: SceneFormat,
    /// The line of each key (of the header for TOML tables).
    lines: HashMap<String, usize>,
    /// JSON only: the line of each table's closing brace.
    ends: HashMap<String, usize>,
}

impl Text {
    pub(crate) fn file(&self) -> &'static Path {
        file_of(self.format)
    }

    /// The line where `path` is written; for an element of an array value
    /// (`camera.position[1]`) the line of the array.
    #[track_caller]
    pub(crate) fn line(&self, path: &str) -> usize {
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
    pub(crate) fn table_line(&self, path: &str) -> usize {
        match self.format {
            SceneFormat::Toml => self.line(path),
            SceneFormat::Json => self.ends[path],
        }
    }

    #[track_caller]
    pub(crate) fn parse_ok(&self) -> Scene {
        parse_ok(&self.text, self.format)
    }

    #[track_caller]
    pub(crate) fn parse_err(&self) -> SceneError {
        parse_err(&self.text, self.format)
    }
}

pub(crate) struct Writer {
    out: Vec<String>,
    format: SceneFormat,
    lines: HashMap<String, usize>,
    ends: HashMap<String, usize>,
}

impl Writer {
    pub(crate) fn new(format: SceneFormat) -> Self {
        Writer {
            out: Vec::new(),
            format,
            lines: HashMap::new(),
            ends: HashMap::new(),
        }
    }

    /// Writes a line that holds `path` (the first such line counts).
    pub(crate) fn line(&mut self, path: &str, text: String) {
        self.out.push(text);
        let n = self.out.len();
        self.lines.entry(path.to_string()).or_insert(n);
    }

    pub(crate) fn plain(&mut self, text: String) {
        self.out.push(text);
    }

    /// An empty line between TOML tables (not at the top).
    pub(crate) fn blank(&mut self) {
        if !self.out.is_empty() {
            self.out.push(String::new());
        }
    }

    /// Ends `path`'s table with `text` (a JSON closing brace).
    pub(crate) fn end(&mut self, path: &str, text: String) {
        self.out.push(text);
        self.ends.insert(path.to_string(), self.out.len());
    }

    pub(crate) fn comma(&mut self) {
        self.out.last_mut().unwrap().push(',');
    }

    pub(crate) fn finish(self) -> Text {
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
pub(crate) fn toml_table(w: &mut Writer, header: &str, path: &str, table: &Table) {
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
pub(crate) fn json_members(w: &mut Writer, path: &str, table: &Table, depth: usize) {
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
pub(crate) fn base() -> Doc {
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
pub(crate) fn two_spheres() -> Doc {
    base()
        .set("spheres[1].center", "[1, 0, -1]")
        .set("spheres[1].radius", "0.25")
        .set("spheres[1].material", "\"blue\"")
}

/// `base()` plus a second, valid triangle.
pub(crate) fn two_triangles() -> Doc {
    base()
        .set(
            "triangles[1].vertices",
            "[[0, 0, -3], [2, 0, -3], [0, 2, -3]]",
        )
        .set("triangles[1].material", "\"red\"")
}

/// `base()` plus a mesh whose OBJ does not exist: fine for every check that
/// comes before the OBJ is read (its keys, material, scale, rotate, translate).
pub(crate) fn with_mesh() -> Doc {
    base()
        .set("meshes[0].path", "\"models/none.obj\"")
        .set("meshes[0].material", "\"red\"")
}

/// Both renderings of `doc` must be rejected with `key`, on the line where
/// that key (or the array holding that element) is written.
#[track_caller]
pub(crate) fn assert_rejected(doc: &Doc, key: &str, words: &[&str]) {
    for text in doc.both() {
        assert_rejected_text(&text, key, words);
    }
}

#[track_caller]
pub(crate) fn assert_rejected_text(text: &Text, key: &str, words: &[&str]) {
    let e = text.parse_err();
    assert_error(&e, text.file(), Some(text.line(key)), Some(key), words);
}

/// Both renderings of `doc` must parse, to the same scene; returns it.
#[track_caller]
pub(crate) fn assert_accepted(doc: &Doc) -> Scene {
    let [toml, json] = doc.both();
    let scene = toml.parse_ok();
    assert_eq!(scene, json.parse_ok(), "TOML and JSON disagree");
    scene
}

#[test]
pub(crate) fn the_doc_helper_writes_what_it_says() {
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
