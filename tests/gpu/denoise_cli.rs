//! `kdray denoise` end to end: an EXR in, EXR or PNG out (atomically), and
//! every bad input a one-line error naming the file, exit code 2, never a
//! panic.

use crate::common;

use common::{run_kdray, Run, TempDir};
use kdray::output::exr::{read_exr_rgb, write_exr_atomic};
use kdray::output::read_png_rgb;

fn assert_usage_error(run: &Run, names: &str) {
    assert_eq!(run.code, 2, "{run:#?}");
    assert!(!run.panicked(), "{run:#?}");
    let line = run.one_error_line();
    assert!(line.contains(names), "{line:?} should name {names}");
}

/// A noisy 48 x 32 gradient, its albedo and its normals.
fn write_inputs(dir: &TempDir) {
    let (w, h) = (48u32, 32u32);
    let mut color = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let n = ((x * 7919 + y * 104_729) % 101) as f32 / 100.0;
            let v = 0.2 + x as f32 / w as f32 + 0.5 * n;
            color.extend([v, v * 0.8, v * 0.5]);
        }
    }
    let pixels = (w * h) as usize;
    write_exr_atomic(&dir.path.join("noisy.exr"), w, h, &color).unwrap();
    write_exr_atomic(
        &dir.path.join("albedo.exr"),
        w,
        h,
        &[0.6f32; 3].repeat(pixels),
    )
    .unwrap();
    write_exr_atomic(
        &dir.path.join("normal.exr"),
        w,
        h,
        &[0.0f32, 0.0, 1.0].repeat(pixels),
    )
    .unwrap();
    write_exr_atomic(&dir.path.join("small.exr"), 8, 8, &[0.5f32; 8 * 8 * 3]).unwrap();
}

#[test]
fn denoise_writes_exr_and_png() {
    let dir = TempDir::new("denoise-cli");
    write_inputs(&dir);
    let run = run_kdray(&dir.path, &["denoise", "noisy.exr", "-o", "out.exr"], &[]);
    assert_eq!(run.code, 0, "{run:#?}");
    let (w, h, out) = read_exr_rgb(&dir.path.join("out.exr")).unwrap();
    assert_eq!((w, h), (48, 32));
    assert!(out.iter().all(|v| v.is_finite() && *v >= 0.0));
    let run = run_kdray(
        &dir.path,
        &[
            "denoise",
            "noisy.exr",
            "--albedo",
            "albedo.exr",
            "--normal",
            "normal.exr",
            "--hdr",
            "-o",
            "out.png",
            "--stats",
        ],
        &[],
    );
    assert_eq!(run.code, 0, "{run:#?}");
    let (w, h, rgb) = read_png_rgb(&dir.path.join("out.png")).unwrap();
    assert_eq!((w, h), (48, 32));
    assert!(rgb.iter().any(|&v| v > 0), "not all black");
    // --stats: one JSON object of the image and its times.
    let stats: serde_json::Value = serde_json::from_str(run.stdout.trim()).expect("JSON stats");
    assert_eq!(
        (
            &stats["width"],
            &stats["height"],
            &stats["input_channels"],
            &stats["tiles"]
        ),
        (&48.into(), &32.into(), &9.into(), &1.into()),
        "{stats}"
    );
    for key in ["setup_ms", "denoise_ms"] {
        assert!(
            stats[key].as_f64().is_some_and(|ms| ms > 0.0),
            "{key}: {stats}"
        );
    }
    let names: Vec<String> = std::fs::read_dir(&dir.path)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(
        names.iter().all(|n| !n.contains(".tmp")),
        "a temporary file was left: {names:?}"
    );
}

#[test]
fn bad_inputs_are_one_line_usage_errors() {
    let dir = TempDir::new("denoise-cli-bad");
    write_inputs(&dir);
    let bytes = std::fs::read(dir.path.join("noisy.exr")).unwrap();
    std::fs::write(dir.path.join("cut.exr"), &bytes[..bytes.len() / 2]).unwrap();
    std::fs::write(dir.path.join("header.exr"), &bytes[..40]).unwrap();
    std::fs::write(dir.path.join("text.exr"), "not an image").unwrap();
    std::fs::write(dir.path.join("picture.png"), "whatever").unwrap();
    let cases: [(&[&str], &str); 7] = [
        (&["denoise", "missing.exr", "-o", "o.exr"], "missing.exr"),
        (&["denoise", "cut.exr", "-o", "o.exr"], "cut.exr"),
        (&["denoise", "header.exr", "-o", "o.exr"], "header.exr"),
        (&["denoise", "text.exr", "-o", "o.exr"], "text.exr"),
        (&["denoise", "picture.png", "-o", "o.exr"], "picture.png"),
        (
            &[
                "denoise",
                "noisy.exr",
                "--albedo",
                "small.exr",
                "--normal",
                "normal.exr",
                "-o",
                "o.exr",
            ],
            "small.exr",
        ),
        (&["denoise", "noisy.exr", "-o", "o.jpg"], "o.jpg"),
    ];
    for (args, names) in cases {
        assert_usage_error(&run_kdray(&dir.path, args, &[]), names);
    }
    // clap's own refusals: a normal without an albedo and the reverse.
    for args in [
        &[
            "denoise",
            "noisy.exr",
            "--normal",
            "normal.exr",
            "-o",
            "o.exr",
        ][..],
        &[
            "denoise",
            "noisy.exr",
            "--albedo",
            "albedo.exr",
            "-o",
            "o.exr",
        ][..],
    ] {
        let run = run_kdray(&dir.path, args, &[]);
        assert_eq!(run.code, 2, "{run:#?}");
        assert!(!run.panicked());
    }
    assert!(!dir.path.join("o.exr").exists());
}
