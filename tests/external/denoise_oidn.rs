//! `kdray denoise` against native Open Image Denoise 1.4.3: the same noisy
//! path-traced render denoised by kdray's kernels and by OIDN's library
//! (scripts/oidn_denoise.py, through the `oidn` wheel), with and without
//! albedo and normal, must agree to a PSNR of at least 45 dB on the HDR
//! image (peak: the largest value of OIDN's output).
//!
//! Needs python3 with the `oidn` 0.2.1 and `OpenEXR` wheels
//! (scripts/test.sh external installs them).

use std::path::Path;
use std::process::Command;

use crate::common;

use common::{repo_path, run_kdray, TempDir};
use kdray::output::exr::{read_exr_rgb, write_exr_atomic};

const MIN_PSNR_DB: f64 = 45.0;

fn python_has_the_wheels() {
    let probe = Command::new("python3")
        .args([
            "-c",
            "import importlib.util, sys, OpenEXR; sys.exit(importlib.util.find_spec('oidn') is None)",
        ])
        .env("PYTHONDONTWRITEBYTECODE", "1")
        .output();
    let ok = probe.as_ref().is_ok_and(|o| o.status.success());
    assert!(
        ok,
        "tests/external/denoise_oidn.rs needs python3 with the oidn and OpenEXR wheels: run \
         scripts/test.sh external (or python3 -m pip install oidn==0.2.1 OpenEXR==3.5.3): {probe:?}"
    );
}

/// OIDN's denoise of `input` (with `aux`: albedo and normal) into `output`.
fn oidn(dir: &Path, input: &str, aux: Option<(&str, &str)>, output: &str) {
    let script = repo_path("scripts/oidn_denoise.py");
    let mut args = vec![script.to_str().unwrap().to_string(), input.into()];
    if let Some((albedo, normal)) = aux {
        args.extend([
            "--albedo".into(),
            albedo.into(),
            "--normal".into(),
            normal.into(),
        ]);
    }
    args.extend(["-o".into(), output.into()]);
    let out = Command::new("python3")
        .args(&args)
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "oidn_denoise.py failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// PSNR of `test` against `reference`, in dB, with the reference's
/// largest value as the peak.
fn psnr(test: &[f32], reference: &[f32]) -> f64 {
    assert_eq!(test.len(), reference.len());
    let peak = reference.iter().fold(0.0f64, |m, &v| m.max(f64::from(v)));
    let mse = test
        .iter()
        .zip(reference)
        .map(|(&a, &b)| (f64::from(a) - f64::from(b)).powi(2))
        .sum::<f64>()
        / test.len() as f64;
    10.0 * (peak * peak / mse).log10()
}

#[test]
fn kdray_denoise_agrees_with_native_oidn() {
    python_has_the_wheels();
    let dir = TempDir::new("denoise-oidn");
    let scene = repo_path("scenes/cornell_box.toml");
    let (w, h) = (320u32, 180u32);
    let (ws, hs) = (w.to_string(), h.to_string());
    let render = run_kdray(
        &dir.path,
        &[
            "render",
            scene.to_str().unwrap(),
            "--integrator",
            "path",
            "--samples",
            "4",
            "--width",
            &ws,
            "--height",
            &hs,
            "-o",
            "noisy.exr",
        ],
        &[],
    );
    assert_eq!(render.code, 0, "{}", render.stderr_text());
    // Constant feature images: a grey albedo and normals facing the camera.
    let pixels = (w * h) as usize;
    let albedo: Vec<f32> = [0.5f32, 0.5, 0.5].repeat(pixels);
    let normal: Vec<f32> = [0.0f32, 0.0, 1.0].repeat(pixels);
    write_exr_atomic(&dir.path.join("albedo.exr"), w, h, &albedo).unwrap();
    write_exr_atomic(&dir.path.join("normal.exr"), w, h, &normal).unwrap();

    let (_, _, noisy) = read_exr_rgb(&dir.path.join("noisy.exr")).unwrap();
    for aux in [None, Some(("albedo.exr", "normal.exr"))] {
        let mut args = vec!["denoise", "noisy.exr", "-o", "kdray.exr"];
        if let Some((a, n)) = aux {
            args.extend(["--albedo", a, "--normal", n]);
        }
        let run = run_kdray(&dir.path, &args, &[]);
        assert_eq!(run.code, 0, "{}", run.stderr_text());
        oidn(&dir.path, "noisy.exr", aux, "oidn.exr");
        let (_, _, ours) = read_exr_rgb(&dir.path.join("kdray.exr")).unwrap();
        let (_, _, theirs) = read_exr_rgb(&dir.path.join("oidn.exr")).unwrap();
        let agreement = psnr(&ours, &theirs);
        let change = psnr(&noisy, &theirs);
        eprintln!(
            "albedo and normal: {}: kdray vs OIDN {agreement:.2} dB; the noisy input vs OIDN {change:.2} dB",
            aux.is_some()
        );
        assert!(
            agreement >= MIN_PSNR_DB,
            "albedo and normal: {}: kdray's denoise is {agreement:.2} dB from OIDN's",
            aux.is_some()
        );
        // The comparison means something: OIDN changed the image far more
        // than kdray differs from it.
        assert!(change < agreement - 10.0, "{change} dB");
    }
}
