//! An animation's frames into an MP4 with ffmpeg, when it is installed
//! (kdray links no video encoder); otherwise the command that would do it.

use std::path::Path;
use std::process::Command;

use super::plan::{frame_digits, FarmPlan, Finished};
use crate::error::{Error, Result};

/// ffmpeg's arguments for DIR's frames into `output` at `fps`: H.264 where
/// ffmpeg has it, 4:2:0 colour for players, sides padded to even numbers
/// (4:2:0 needs them).
fn ffmpeg_args(dir: &Path, frames: u32, fps: f64, output: &Path) -> Vec<String> {
    let pattern = dir.join(format!("%0{}d.png", frame_digits(frames)));
    vec![
        "-y".into(),
        "-loglevel".into(),
        "error".into(),
        "-framerate".into(),
        format!("{fps}"),
        "-i".into(),
        pattern.to_string_lossy().into_owned(),
        "-vf".into(),
        "pad=ceil(iw/2)*2:ceil(ih/2)*2".into(),
        "-pix_fmt".into(),
        "yuv420p".into(),
        "-f".into(),
        "mp4".into(),
        output.to_string_lossy().into_owned(),
    ]
}

/// Encodes DIR's frames into the plan's MP4 (written to a temporary file,
/// then renamed into place) when ffmpeg is on the PATH.
pub fn encode(plan: &FarmPlan, dir: &Path, frames: u32, fps: f64) -> Result<Finished> {
    let out = plan.final_path(dir);
    let words = ffmpeg_args(dir, frames, fps, &out);
    let ffmpeg_command = std::iter::once("ffmpeg".to_string())
        .chain(words.iter().map(|w| shell_word(w)))
        .collect::<Vec<_>>()
        .join(" ");
    let Some(ffmpeg) = super::find_on_path("ffmpeg") else {
        return Ok(Finished::Frames {
            frames,
            video: None,
            ffmpeg_command,
        });
    };
    let tmp = dir.join(format!(".{}.mp4.tmp-{}", plan.stem(), std::process::id()));
    let mut args = ffmpeg_args(dir, frames, fps, &tmp);
    args.truncate(args.len() - 1);
    args.push(tmp.to_string_lossy().into_owned());
    let status = Command::new(ffmpeg).args(&args).status();
    let result = match status {
        Ok(s) if s.success() => std::fs::rename(&tmp, &out).map_err(|source| Error::File {
            path: out.clone(),
            what: "cannot rename the temporary file into place",
            source,
        }),
        Ok(s) => Err(Error::Output(format!(
            "ffmpeg failed ({s}): {ffmpeg_command}"
        ))),
        Err(e) => Err(Error::Output(format!(
            "cannot run ffmpeg ({e}): {ffmpeg_command}"
        ))),
    };
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result?;
    Ok(Finished::Frames {
        frames,
        video: Some(out),
        ffmpeg_command,
    })
}

/// A word as `sh` reads it back: bare when plain, else single-quoted.
fn shell_word(word: &str) -> String {
    let plain = |c: char| c.is_ascii_alphanumeric() || "-_./:=%+,".contains(c);
    match word.chars().all(plain) && !word.is_empty() {
        true => word.to_string(),
        false => format!("'{}'", word.replace('\'', r"'\''")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_command_reads_the_frames_by_their_digits() {
        let args = ffmpeg_args(Path::new("/out"), 48, 24.0, Path::new("/out/orbit.mp4"));
        assert!(args.contains(&"/out/%04d.png".to_string()));
        assert_eq!(args.last().unwrap(), "/out/orbit.mp4");
        let args = ffmpeg_args(Path::new("/out"), 20_000, 30.0, Path::new("/out/o.mp4"));
        assert!(args.contains(&"/out/%05d.png".to_string()));
    }

    #[test]
    fn shell_words_are_quoted_when_needed() {
        assert_eq!(shell_word("/out/%04d.png"), "/out/%04d.png");
        assert_eq!(shell_word("pad=ceil(iw/2)*2"), "'pad=ceil(iw/2)*2'");
    }
}
