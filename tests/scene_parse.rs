use kdray::scene::{parse_scene, SceneFormat};
use std::path::Path;
fn t(label: &str, text: &str) {
    match parse_scene(text, Path::new("/tmp/probe/s.toml"), SceneFormat::Toml) {
        Ok(s) => println!("TOML {label}: OK {:?}", s.camera),
        Err(e) => println!("TOML {label}: line={:?} key={:?} | {e}", e.line, e.key),
    }
}
#[test]
fn probe() {
    for v in ["1e999", "-nan", "+inf", "nan", "1e308", "60"] {
        t(v, &format!("[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0, 0]\nvfov = {v}\n[[lights]]\nposition = [5, 5, 5]\n"));
    }
    t(
        "up default",
        "[camera]\nposition = [0, 5, 0]\nlook_at = [0, 0, 0]\n[[lights]]\nposition = [5, 5, 5]\n",
    );
    t("dup", "[camera]\nposition = [0, 5, 0]\nlook_at = [0, 0, 0]\n[[lights]]\nposition = [5, 5, 5]\n[materials.a]\ndiffuse=[1,1,1]\n[materials.a]\ndiffuse=[1,1,1]\n");
    t(
        "dupkey",
        "[camera]\nposition = [0, 5, 0]\nposition = [0, 0, 0]\n[[lights]]\nposition = [5, 5, 5]\n",
    );
}
