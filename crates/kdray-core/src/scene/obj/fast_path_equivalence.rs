//! The fast path against the reference parser: on generated OBJ files, with
//! and without materials, on any number of chunks, the same mesh bit for
//! bit or the fast path declines; and the chunks cover the text.

use super::chunk::number;
use super::fast::{parse, split_at_lines, Outcome};
use super::material_replay::MaterialFiles;
use super::reference::parse_reference;
use super::{parse_obj, parse_obj_bytes};
use crate::scene::error::SceneError;
use crate::scene::mesh::Mesh;
use proptest::prelude::*;
use std::path::{Path, PathBuf};

/// The reference parser's mesh and `f` count, or its error, as text:
/// `{:?}` writes every f64 in its shortest round-trip form, so equal text
/// is equal bits (it tells -0.0 from 0.0, which `==` does not).
fn reference(text: &str) -> Result<(String, usize), String> {
    let mut faces = 0;
    parse_reference(text, Path::new("m.obj"), false, &mut |_| {}, &mut faces)
        .map(|mesh| (format!("{mesh:?}"), faces))
        .map_err(|e| e.to_string())
}

/// The fast path on `threads` chunks, as `reference` writes it; None
/// where it leaves the text to the reference parser.
fn fast(text: &str, threads: usize) -> Option<(String, usize)> {
    match parse(text.as_bytes(), threads, None) {
        Outcome::Mesh(mesh, faces) => Some((format!("{mesh:?}"), faces)),
        Outcome::Declined { mtl_reads } => {
            assert_eq!(mtl_reads, 0);
            None
        }
    }
}

/// Decimal numbers as exporters write them, and awkward ones: signs,
/// no digits before or after the point, 15 and 16 digits (the fast
/// path's limit), leading zeros, exponents, `inf`, `nan`, junk.
fn number_text() -> impl Strategy<Value = String> {
    prop_oneof![
        4 => (
            prop::sample::select(vec!["", "-", "+"]),
            "[0-9]{0,9}",
            prop::option::of("[0-9]{0,9}"),
        )
            .prop_map(|(sign, int, frac)| match frac {
                Some(frac) => format!("{sign}{int}.{frac}"),
                None => format!("{sign}{int}"),
            }),
        1 => "[-+]?0*[0-9]{13,17}(\\.[0-9]{0,4})?",
        1 => "[-+]?[0-9]{0,3}\\.?[0-9]{0,3}[eE][-+]?[0-9]{1,3}",
        1 => "[-+.0-9eE]{1,6}",
        1 => prop::sample::select(vec![
            "inf", "-inf", "infinity", "NaN", "nan", "1e308", "1e309", "-0", "-0.0",
            "0.1", "0.2", "0.3", "9007199254740993", "999999999999999", "0.000000000000001",
            ".", "-.", "+.5", "5.", "1,5", "0x10", "１",
        ])
        .prop_map(str::to_string),
        1 => any::<f64>().prop_map(|v| v.to_string()),
        1 => any::<f32>().prop_map(|v| v.to_string()),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4096))]

    /// The fast number parser reads exactly what `str::parse` reads.
    #[test]
    fn numbers_parse_as_the_standard_library_parses(text in number_text()) {
        let want = text.parse::<f64>().ok().filter(|v| v.is_finite());
        let got = number(&text);
        prop_assert_eq!(got.map(f64::to_bits), want.map(f64::to_bits), "{:?}", text);
    }
}

/// One line of a generated OBJ file, its numbers still to be chosen
/// (`Obj::text` resolves face corners against the vertices so far).
#[derive(Debug, Clone)]
enum Statement {
    Vertex(Vec<String>),
    Normal(Vec<String>),
    Texture,
    /// Corners: (vertex pick, normal pick, negative, form 0..4: `v`,
    /// `v/vt`, `v//vn`, `v/vt/vn`).
    Face(Vec<(usize, usize, bool, u8)>),
    /// Lines every reader ignores without materials, comments, blanks.
    Other(&'static str),
    /// A line the reference parser refuses or the fast path leaves to it.
    Odd(&'static str),
}

fn statement() -> impl Strategy<Value = Statement> {
    // Coordinates on a small grid, so that faces repeat vertices and lie
    // on lines (zero area), plus any number the number strategy makes.
    let coordinate = prop_oneof![
        6 => prop::sample::select(vec!["0", "1", "-1", "0.5", "-0", "2", "1e-200", "3.25"])
            .prop_map(str::to_string),
        1 => number_text(),
    ];
    prop_oneof![
        8 => prop::collection::vec(coordinate.clone(), 3..=4).prop_map(Statement::Vertex),
        3 => prop::collection::vec(coordinate, 3..=3).prop_map(Statement::Normal),
        1 => Just(Statement::Texture),
        8 => prop::collection::vec((0..64usize, 0..64usize, any::<bool>(), 0..4u8), 3..=6)
            .prop_map(Statement::Face),
        3 => prop::sample::select(vec![
            "", "   ", "# a comment", "#", "o thing", "g group", "s 1", "s off",
            "usemtl gold", "mtllib a.mtl", "vp 0.1 0.2", "l 1 2", "V 1 2 3", "v1 2 3 4",
            "F 1 2 3", "\t", "fo 1 2 3",
        ])
        .prop_map(Statement::Other),
        1 => prop::sample::select(vec![
            "v 1 2", "v 1 2 x", "vn 1 2", "vn 1 2 3 4", "f 1 2", "f 0 1 2", "f 1 2 x",
            "f 1 2 3.0", "f +1 +2 +3", "f 1 2 0000000003", "f 1 2 4294967299", "f -1 -2 -999", "f 1 2 99999",
            "f 1//9999 2 3", "v 1 2 3 \\", "f 1/1/1/1 2/2/2/2 3//-1", "f 1/x 2/y/ 3/z/",
            "v 1e400 0 0", "vn nan 0 0",
        ])
        .prop_map(Statement::Odd),
    ]
}

/// How a generated line is written around its statement.
#[derive(Debug, Clone)]
struct Layout {
    indent: &'static str,
    gap: &'static str,
    comment: &'static str,
    crlf: bool,
}

fn layout() -> impl Strategy<Value = Layout> {
    (
        prop::sample::select(vec!["", "", " ", "\t "]),
        prop::sample::select(vec![" ", " ", " ", "  ", "\t", " \x0c", "\r "]),
        prop::sample::select(vec!["", "", "", " # c", "#glued", " \t"]),
        any::<bool>(),
    )
        .prop_map(|(indent, gap, comment, crlf)| Layout {
            indent,
            gap,
            comment,
            crlf,
        })
}

/// A whole file: its lines, a byte order mark or not, a last newline or
/// not. Half the files are kept valid (no odd lines, numbers that parse,
/// no face before the first vertex), so that the fast path takes them.
fn obj_text() -> impl Strategy<Value = String> {
    (
        prop::collection::vec((statement(), layout()), 0..60),
        any::<bool>(),
        any::<bool>(),
        any::<bool>(),
    )
        .prop_map(|(lines, bom, last_newline, valid)| {
            let (mut positions, mut normals) = (0usize, 0usize);
            let mut text = String::new();
            if bom {
                text.push('\u{feff}');
            }
            let finite = |x: &String| match x.parse::<f64>() {
                Ok(v) if v.is_finite() => x.clone(),
                _ => "0".to_string(),
            };
            let lines: Vec<_> = lines
                .into_iter()
                .filter(|(s, _)| !valid || !matches!(s, Statement::Odd(_)))
                .map(|(s, l)| match s {
                    Statement::Vertex(xyz) if valid => {
                        (Statement::Vertex(xyz.iter().map(finite).collect()), l)
                    }
                    Statement::Normal(xyz) if valid => {
                        (Statement::Normal(xyz.iter().map(finite).collect()), l)
                    }
                    s => (s, l),
                })
                .collect();
            for (i, (statement, l)) in lines.iter().enumerate() {
                let body = match statement {
                    Statement::Vertex(xyz) => {
                        positions += 1;
                        format!("v{}{}", l.gap, xyz.join(l.gap))
                    }
                    Statement::Normal(xyz) => {
                        normals += 1;
                        format!("vn{}{}", l.gap, xyz.join(l.gap))
                    }
                    Statement::Texture => "vt 0.5 0.25".to_string(),
                    // A valid file has no face before its first vertex.
                    Statement::Face(_) if valid && positions == 0 => "# no face".to_string(),
                    Statement::Face(corners) => {
                        let tokens: Vec<String> = corners
                            .iter()
                            .map(|&(v, n, negative, form)| {
                                // In range when anything is defined;
                                // index 1 (out of range) when nothing is.
                                let pick = |p: usize, defined: usize| match defined {
                                    0 => "1".to_string(),
                                    d if negative => format!("-{}", p % d + 1),
                                    d => format!("{}", p % d + 1),
                                };
                                let v = pick(v, positions);
                                let n = pick(n, normals);
                                // `v/vt` names no normal; a valid file
                                // names one only once one is defined.
                                match form {
                                    0 => v,
                                    _ if valid && normals == 0 => format!("{v}/3"),
                                    1 => format!("{v}/{n}"),
                                    2 => format!("{v}//{n}"),
                                    _ => format!("{v}/7/{n}"),
                                }
                            })
                            .collect();
                        format!("f{}{}", l.gap, tokens.join(l.gap))
                    }
                    Statement::Other(s) | Statement::Odd(s) => s.to_string(),
                };
                text.push_str(l.indent);
                text.push_str(&body);
                text.push_str(l.comment);
                if i + 1 < lines.len() || last_newline {
                    text.push_str(if l.crlf { "\r\n" } else { "\n" });
                }
            }
            text
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1024))]

    /// On 1, 2, 3 and 5 chunks the fast path gives the reference
    /// parser's mesh bit for bit, or leaves the file to it; it never
    /// gives a mesh for a file the reference refuses. `parse_obj` (which
    /// picks the path) gives exactly the reference's mesh or error.
    #[test]
    fn fast_path_gives_the_reference_mesh(text in obj_text()) {
        let want = reference(&text);
        let body = text.strip_prefix('\u{feff}').unwrap_or(&text);
        for threads in [1, 2, 3, 5] {
            if let Some(got) = fast(body, threads) {
                prop_assert_eq!(Ok(got), want.clone(), "{} threads", threads);
            }
        }
        let chosen = parse_obj(&text, Path::new("m.obj"), false)
            .map(|mesh| format!("{mesh:?}"))
            .map_err(|e| e.to_string());
        prop_assert_eq!(chosen, want.map(|(mesh, _)| mesh));
    }
}

/// A folder of MTL files for the material property: two that define
/// `teal` (the first definition wins), one with an error. One folder
/// for every run, so that runs leave nothing new behind; each file is
/// renamed into place, so a run beside this one never reads half a file.
fn mtl_folder() -> &'static Path {
    static FOLDER: std::sync::OnceLock<std::path::PathBuf> = std::sync::OnceLock::new();
    FOLDER.get_or_init(|| {
        let dir = std::env::temp_dir().join("kdray-obj-chunks-test");
        std::fs::create_dir_all(&dir).unwrap();
        let files = [
            (
                "a.mtl",
                "newmtl gold\nKd 1 0.8 0\nNs 20\nnewmtl teal\nKd 0 0.5 0.5\n",
            ),
            (
                "b.mtl",
                "newmtl teal\r\nKd 1 1 1\r\nnewmtl my red\nKa 1\nKd 1 0 0\n",
            ),
            ("bad.mtl", "newmtl x\nKd 1 1\n"),
        ];
        for (name, text) in files {
            let part = dir.join(format!("{name}.{}", std::process::id()));
            std::fs::write(&part, text).unwrap();
            std::fs::rename(&part, dir.join(name)).unwrap();
        }
        dir
    })
}

/// A parse with materials of `text` as `m.obj` in `mtl_folder()`: the
/// mesh or error as `reference` writes it, and the files the observer
/// was told of.
fn with_materials(
    text: &str,
    parser: impl FnOnce(&str, &Path, &mut dyn FnMut(&Path), &mut usize) -> Result<Mesh, SceneError>,
) -> (Result<(String, usize), String>, Vec<PathBuf>) {
    let mut read = Vec::new();
    let mut faces = 0;
    let path = mtl_folder().join("m.obj");
    let result = parser(text, &path, &mut |p| read.push(p.to_path_buf()), &mut faces)
        .map(|mesh| (format!("{mesh:?}"), faces))
        .map_err(|e| e.to_string());
    (result, read)
}

/// Generated files with material statements inserted at random lines.
fn obj_text_with_materials() -> impl Strategy<Value = String> {
    let statement = prop_oneof![
        12 => prop::sample::select(vec![
            "usemtl gold", "usemtl teal", "usemtl  my red # c", "mtllib a.mtl",
            "mtllib b.mtl a.mtl", "mtllib  a.mtl\t# again",
        ]),
        1 => prop::sample::select(vec![
            "usemtl nope", "usemtl", "usemtl # none", "mtllib missing.mtl",
            "mtllib bad.mtl", "mtllib", "Usemtl gold",
        ]),
    ];
    (
        prop::bool::weighted(0.8),
        obj_text(),
        prop::collection::vec((any::<prop::sample::Index>(), statement), 0..8),
    )
        .prop_map(|(header, text, inserts)| {
            let mut lines: Vec<String> = text.split('\n').map(str::to_string).collect();
            for (at, statement) in inserts {
                let at = at.index(lines.len() + 1);
                lines.insert(at, statement.to_string());
            }
            let body = lines.join("\n");
            if header {
                format!("mtllib a.mtl b.mtl\nusemtl gold\n{body}")
            } else {
                body
            }
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// With materials too: the same mesh (materials in order of first
    /// use, each face's index), error, and MTL files read, in order, on
    /// 1, 2, 3 and 5 chunks and through `parse_obj_bytes`.
    #[test]
    fn fast_path_gives_the_reference_mesh_with_materials(
        text in obj_text_with_materials()
    ) {
        let (want, want_read) = with_materials(&text, |t, p, r, f| {
            parse_reference(t, p, true, r, f)
        });
        let body = text.strip_prefix('\u{feff}').unwrap_or(&text).to_string();
        for threads in [1, 2, 3, 5] {
            let mut outcome = None;
            let (_, read) = with_materials(&body, |t, path, on_read, _| {
                outcome = Some(parse(t.as_bytes(), threads, Some(MaterialFiles { path, on_read })));
                Err(SceneError::new(path, None, None, "unused"))
            });
            match outcome.unwrap() {
                Outcome::Mesh(mesh, faces) => {
                    prop_assert_eq!(Ok((format!("{mesh:?}"), faces)), want.clone());
                    prop_assert_eq!(&read, &want_read);
                }
                Outcome::Declined { mtl_reads } => {
                    prop_assert_eq!(mtl_reads, read.len());
                    prop_assert!(want_read.starts_with(&read));
                }
            }
        }
        let chosen = with_materials(&text, |t, p, r, f| parse_obj_bytes(t.as_bytes(), p, true, r, f));
        prop_assert_eq!(chosen, (want, want_read));
    }
}

/// The generated files exercise both outcomes: the fast path takes many
/// of them (so the property compares meshes), and the reference parser
/// refuses many.
#[test]
fn generated_files_reach_both_paths() {
    use proptest::strategy::ValueTree;
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let (mut taken, mut refused, mut triangles) = (0, 0, 0);
    for _ in 0..400 {
        let text = obj_text().new_tree(&mut runner).unwrap().current();
        let body = text.strip_prefix('\u{feff}').unwrap_or(&text);
        if let Outcome::Mesh(mesh, _) = parse(body.as_bytes(), 2, None) {
            taken += 1;
            triangles += mesh.triangles.len();
        }
        refused += usize::from(reference(&text).is_err());
    }
    assert!(
        taken >= 100 && refused >= 100,
        "{taken} taken, {refused} refused"
    );
    assert!(triangles >= 1000, "{triangles} triangles");

    // With materials: meshes using two materials or more, and refusals
    // after an MTL file was read.
    let (mut mixed, mut refused_after_reading) = (0, 0);
    for _ in 0..400 {
        let text = obj_text_with_materials()
            .new_tree(&mut runner)
            .unwrap()
            .current();
        let body = text.strip_prefix('\u{feff}').unwrap_or(&text);
        let path = mtl_folder().join("m.obj");
        let files = MaterialFiles {
            path: &path,
            on_read: &mut |_| {},
        };
        match parse(body.as_bytes(), 2, Some(files)) {
            Outcome::Mesh(mesh, _) => mixed += usize::from(mesh.materials.len() >= 2),
            Outcome::Declined { mtl_reads } => refused_after_reading += usize::from(mtl_reads > 0),
        }
    }
    assert!(mixed >= 30, "{mixed} meshes with two materials or more");
    assert!(
        refused_after_reading >= 20,
        "{refused_after_reading} refused after reading"
    );
}

/// The fast path does take the valid files it is meant for (else the
/// property above would compare nothing): faces in every form, negative
/// indices across a chunk boundary, comments, CRLF, ignored statements.
#[test]
fn fast_path_takes_ordinary_files() {
    let text = "# header\r\nmtllib a.mtl\r\nv 0 0 0\r\nv 1 0 0 1\nv 0 1 0\nv 1 1 0\n\
                vn 0 0 1\nvt 0 0\nusemtl gold\n\n  f 1 2 3 # c\nf 1/1 2/1 3/1\n\
                f 1//1 2//1 3//1\nf 1/1/1 -3/1/-1 -1/1/1 4/7/1\ng g\ns off\n\
                v 2 2 0\nf -1 -2 -3\nf 1 2 2\n";
    let want = reference(text).unwrap();
    assert_eq!(want.1, 6);
    for threads in 1..=6 {
        assert_eq!(
            fast(text, threads).as_ref(),
            Some(&want),
            "{threads} threads"
        );
    }
}

/// Files the reference parser refuses, with the refusal in a later chunk
/// than the vertices it is about, go to the reference parser.
#[test]
fn errors_are_left_to_the_reference_parser() {
    for text in [
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\n",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf -1 -2 -4\n",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//2\n",
        "v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 0\n",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nv 1 2\n",
    ] {
        assert!(reference(text).is_err(), "{text}");
        for threads in 1..=5 {
            assert_eq!(fast(text, threads), None, "{text}, {threads} threads");
        }
    }
}

#[test]
fn chunks_end_after_newlines_and_cover_the_text() {
    let text = "v 1 2 3\r\nf 1 2 3\n\nvn 0 0 1\nx";
    for parts in 1..=8 {
        let pieces = split_at_lines(text.as_bytes(), parts);
        assert_eq!(pieces.len(), parts);
        assert_eq!(pieces.concat(), text.as_bytes());
        for (i, piece) in pieces.iter().enumerate() {
            let last = pieces[i + 1..].iter().all(|p| p.is_empty());
            assert!(last || piece.ends_with(b"\n"), "{pieces:?}");
        }
    }
    let none: [&[u8]; 3] = [b"", b"", b""];
    assert_eq!(split_at_lines(b"", 3), none);
}
