use kdray::scene::{parse_scene, SceneFormat};
use std::path::Path;

const CAM: &str = "[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0, 0]\n\n[[lights]]\nposition = [5, 5, 5]\n\n[materials.red]\ndiffuse = [0.7, 0, 0]\n";

fn t(label: &str, text: &str) {
    match parse_scene(text, Path::new("/tmp/probe/s.toml"), SceneFormat::Toml) {
        Ok(_) => println!("TOML {label}: OK"),
        Err(e) => println!("TOML {label}: line={:?} key={:?} | {e}", e.line, e.key),
    }
}
fn j(label: &str, text: &str) {
    match parse_scene(text, Path::new("/tmp/probe/s.json"), SceneFormat::Json) {
        Ok(_) => println!("JSON {label}: OK"),
        Err(e) => println!("JSON {label}: line={:?} key={:?} | {e}", e.line, e.key),
    }
}

#[test]
fn probe() {
    t("unknown top", &format!("{CAM}\nfoo = 1\n"));
    t("unknown in camera", "[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0, 0]\nfov = 3\n[[lights]]\nposition = [5, 5, 5]\n");
    t("unknown in sphere", &format!("{CAM}\n[[spheres]]\ncenter = [0,0,0]\nradius = 1\nmaterial = \"red\"\n[[spheres]]\ncenter = [0,0,0]\nradius = 1\ncolor = 3\nmaterial = \"red\"\n"));
    t("missing radius", &format!("{CAM}\n[[spheres]]\ncenter = [0,0,0]\nradius = 1\nmaterial = \"red\"\n[[spheres]]\ncenter = [0,0,0]\nmaterial = \"red\"\n"));
    t("wrong type", &format!("{CAM}\n[[spheres]]\ncenter = [0,0,0]\nradius = 1\nmaterial = \"red\"\n[[spheres]]\ncenter = [0,0,0]\nradius = \"big\"\nmaterial = \"red\"\n"));
    t(
        "short vec",
        "[camera]\nposition = [0, 0]\nlook_at = [0, 0, 0]\n",
    );
    t("missing camera", "[[lights]]\nposition = [5, 5, 5]\n");
    t("empty", "");
    t(
        "nan",
        "[camera]\nposition = [0, nan, 1]\nlook_at = [0, 0, 0]\n[[lights]]\nposition = [5, 5, 5]\n",
    );
    t("inf", "[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0, 0]\nvfov = inf\n[[lights]]\nposition = [5, 5, 5]\n");
    t("malformed", "[camera\nposition = [0, 0, 1]\n");
    t(
        "malformed2",
        "[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0, \n",
    );
    t("width", &format!("{CAM}[render]\nwidth = 0\n"));
    t("width neg", &format!("{CAM}[render]\nwidth = -1\n"));
    t("width float", &format!("{CAM}[render]\nwidth = 1.5\n"));
    t(
        "shadow",
        &format!("{CAM}[render]\nshadow_mode = \"hard\"\n"),
    );
    t("inline render", &format!("render = {{ width = 0 }}\n{CAM}"));
    t("dotted", &format!("{CAM}render.width = 0\n"));
    t(
        "mesh scale str",
        &format!("{CAM}[[meshes]]\npath = \"x.obj\"\nscale = \"a\"\n"),
    );
    t(
        "mesh missing",
        &format!("{CAM}[[meshes]]\npath = \"x.obj\"\n"),
    );
    t(
        "no lights",
        "[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0, 0]\n",
    );
    t(
        "lights empty",
        "lights = []\n[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0, 0]\n",
    );
    t(
        "tri verts nan",
        &format!(
            "{CAM}[[triangles]]\nvertices = [[0,0,0],[1,0,0],[0,nan,0]]\nmaterial = \"red\"\n"
        ),
    );
    t(
        "materials not table",
        "materials = 3\n[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0, 0]\n",
    );
    t("mat unknown key", &format!("{CAM}shine = 3\n"));
    t(
        "mat missing diffuse",
        &format!("{CAM}[materials.blue]\nambient = [0,0,0]\n"),
    );

    let base = "{\n  \"camera\": {\n    \"position\": [0, 0, 1],\n    \"look_at\": [0, 0, 0]\n  },\n  \"lights\": [{\"position\": [5, 5, 5]}],\n  \"materials\": {\"red\": {\"diffuse\": [0.7, 0, 0]}}";
    j("unknown top", &format!("{base},\n  \"foo\": 1\n}}"));
    j("unknown sphere", &format!("{base},\n  \"spheres\": [\n    {{\"center\": [0,0,0], \"radius\": 1, \"material\": \"red\"}},\n    {{\"center\": [0,0,0],\n     \"color\": 1, \"radius\": 1, \"material\": \"red\"}}\n  ]\n}}"));
    j("missing radius", &format!("{base},\n  \"spheres\": [\n    {{\"center\": [0,0,0], \"radius\": 1, \"material\": \"red\"}},\n    {{\"center\": [0,0,0],\n     \"material\": \"red\"}}\n  ]\n}}"));
    j("wrong type", &format!("{base},\n  \"spheres\": [\n    {{\"center\": [0,0,0], \"radius\": 1, \"material\": \"red\"}},\n    {{\"center\": [0,0,0],\n     \"radius\": \"big\", \"material\": \"red\"}}\n  ]\n}}"));
    j(
        "1e999",
        &format!("{base},\n  \"render\": {{\n    \"min_intensity\": 1e999\n  }}\n}}"),
    );
    j("-1e999", &format!("{base},\n  \"spheres\": [\n    {{\"center\": [0,-1e999,0], \"radius\": 1, \"material\": \"red\"}}]\n}}"));
    j(
        "NaN",
        &format!("{base},\n  \"render\": {{\n    \"min_intensity\": NaN\n  }}\n}}"),
    );
    j("malformed", "{\n \"camera\": {\n");
    j("malformed2", "{\n \"camera\": {},,\n}");
    j("trailing comma", &format!("{base},\n}}"));
    j("empty", "");
    j("missing camera", "{\"lights\": []}");
    j(
        "lights empty",
        "{\"camera\": {\"position\": [0,0,1], \"look_at\": [0,0,0]},\n \"lights\": []}",
    );
    j(
        "width",
        &format!("{base},\n  \"render\": {{\n    \"width\": 0\n  }}\n}}"),
    );
    j(
        "shadow",
        &format!("{base},\n  \"render\": {{\n    \"shadow_mode\": \"hard\"\n  }}\n}}"),
    );
    j("dup mat", &format!("{base},\n  \"materials\": {{}}\n}}"));
    j("dup key in mat", "{\"camera\": {\"position\": [0,0,1], \"look_at\": [0,0,0]},\n \"lights\": [{\"position\": [1,1,1]}],\n \"materials\": {\"a\": {\"diffuse\": [1,1,1]}, \"a\": {\"diffuse\": [0,1,1]}}}");
    j(
        "mesh scale str",
        &format!("{base},\n  \"meshes\": [{{\"path\": \"x.obj\",\n \"scale\": \"a\"}}]\n}}"),
    );
}
