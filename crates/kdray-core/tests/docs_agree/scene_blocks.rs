//! Every ```toml and ```json block of the documents is read by kdray's scene
//! loader. A block is a whole scene unless an HTML comment on the line
//! before its fence says otherwise:
//!
//! - `<!-- fragment: WHY -->`: part of a scene (WHY says which part); it
//!   must still be valid TOML or JSON;
//! - `<!-- refused: WHY -->`: a scene shown to be refused; valid TOML or
//!   JSON that the loader refuses.
//!
//! A whole scene is parsed as if it were `scenes/doc-example.toml` (or
//! `.json`), so its mesh paths are relative to `scenes/`.

use kdray_core::scene::{parse_scene, SceneFormat};

use super::*;

/// How a block is marked.
#[derive(Debug, PartialEq)]
enum Kind {
    Scene,
    Fragment,
    Refused,
}

struct Block {
    doc: String,
    line: usize,
    format: SceneFormat,
    kind: Kind,
    text: String,
}

/// The ```toml and ```json blocks of `text`, with their marks.
fn blocks(doc: &str, text: &str) -> Vec<Block> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let fence = lines[i].trim_start();
        let format = match fence {
            "```toml" => Some(SceneFormat::Toml),
            "```json" => Some(SceneFormat::Json),
            _ => None,
        };
        let Some(format) = format else {
            if fence.starts_with("```") {
                // Skip any other block whole.
                i += 1;
                while i < lines.len() && !lines[i].trim_start().starts_with("```") {
                    i += 1;
                }
            }
            i += 1;
            continue;
        };
        let indent = lines[i].len() - fence.len();
        let mark = if i > 0 { lines[i - 1].trim() } else { "" };
        let kind = mark_kind(mark).unwrap_or_else(|e| panic!("{doc}:{}: {e}", i));
        let start = i + 1;
        let mut end = start;
        while end < lines.len() && lines[end].trim_start() != "```" {
            end += 1;
        }
        let text: String = lines[start..end]
            .iter()
            .map(|l| format!("{}\n", l.get(indent..).unwrap_or(l.trim_start())))
            .collect();
        out.push(Block {
            doc: doc.to_string(),
            line: start,
            format,
            kind,
            text,
        });
        i = end + 1;
    }
    out
}

/// The kind a mark line gives, or why the mark is malformed.
fn mark_kind(mark: &str) -> Result<Kind, String> {
    let Some(inner) = mark
        .strip_prefix("<!--")
        .and_then(|m| m.strip_suffix("-->"))
    else {
        return Ok(Kind::Scene);
    };
    let inner = inner.trim();
    let (kind, why) = inner
        .split_once(':')
        .ok_or(format!("a block's mark needs a reason: {mark}"))?;
    if why.trim().is_empty() {
        return Err(format!("a block's mark needs a reason: {mark}"));
    }
    match kind.trim() {
        "fragment" => Ok(Kind::Fragment),
        "refused" => Ok(Kind::Refused),
        other => Err(format!(
            "unknown block mark {other:?} (fragment or refused)"
        )),
    }
}

/// Why the block is not what its mark says, or Ok.
fn check(block: &Block) -> Result<(), String> {
    let syntax = match block.format {
        SceneFormat::Toml => toml::from_str::<toml::Value>(&block.text)
            .map(drop)
            .map_err(|e| e.to_string()),
        SceneFormat::Json => serde_json::from_str::<serde_json::Value>(&block.text)
            .map(drop)
            .map_err(|e| e.to_string()),
    };
    syntax.map_err(|e| format!("not valid {:?}: {e}", block.format))?;
    let extension = match block.format {
        SceneFormat::Toml => "toml",
        SceneFormat::Json => "json",
    };
    let path = repo_path(&format!("scenes/doc-example.{extension}"));
    let parsed = parse_scene(&block.text, &path, block.format);
    match (&block.kind, parsed) {
        (Kind::Scene, Err(e)) => Err(format!("the scene loader refuses it: {e}")),
        (Kind::Refused, Ok(_)) => Err("marked refused, but the scene loader reads it".to_string()),
        _ => Ok(()),
    }
}

#[test]
fn every_scene_block_of_the_documents_loads_and_every_fragment_is_marked() {
    let mut wrong = Vec::new();
    let mut scenes = 0;
    for (doc, text) in documents() {
        for block in blocks(&doc, &text) {
            scenes += usize::from(block.kind == Kind::Scene);
            if let Err(why) = check(&block) {
                wrong.push(format!("{}:{}: {why}", block.doc, block.line));
            }
        }
    }
    assert!(
        scenes >= 2,
        "only {scenes} whole scenes found in the documents"
    );
    assert!(
        wrong.is_empty(),
        "scene blocks in the documents:\n{}",
        wrong.join("\n")
    );
}

#[test]
fn a_block_that_is_not_a_scene_fails_unless_marked() {
    let doc = "text\n```toml\n[animation]\nframes = 4\n```\n\
               <!-- fragment: the [animation] table -->\n```toml\n[animation]\nframes = 4\n```\n\
               <!-- refused: a sphere without a radius -->\n```json\n{\"spheres\": [{}]}\n```\n";
    let found = blocks("doc.md", doc);
    let kinds: Vec<&Kind> = found.iter().map(|b| &b.kind).collect();
    assert_eq!(kinds, [&Kind::Scene, &Kind::Fragment, &Kind::Refused]);
    assert!(
        check(&found[0]).is_err(),
        "an unmarked fragment passed as a scene"
    );
    assert_eq!(check(&found[1]), Ok(()));
    assert_eq!(check(&found[2]), Ok(()));
    assert!(mark_kind("<!-- fragment: -->").is_err());
    assert!(mark_kind("<!-- sketch: why -->").is_err());
}
