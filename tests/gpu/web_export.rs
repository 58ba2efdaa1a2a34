//! `kdray web SCENE -o DIR` without a browser: the folder rules, scene
//! errors as `render`'s, and the bundle and contract it writes.

use crate::common;

use std::collections::{BTreeMap, BTreeSet};

use common::*;
use kdray::web::bundle;

#[test]
fn an_existing_folder_that_is_not_a_site_is_refused_untouched() {
    let dir = TempDir::new("web-refuse");
    dir.write("mine/notes.txt", "keep me");
    let seed = repo_path("scenes/seed.toml");
    let run = run_kdray(
        &dir.path,
        &["web", seed.to_str().unwrap(), "-o", "mine"],
        &[],
    );
    assert_eq!(run.code, 2, "{}", run.stderr_text());
    assert!(
        run.one_error_line().contains("is not a kdray site"),
        "{run:?}"
    );
    let names: Vec<_> = std::fs::read_dir(dir.join("mine"))
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, ["notes.txt"], "nothing written");
    dir.write("file", "x");
    let run = run_kdray(
        &dir.path,
        &["web", seed.to_str().unwrap(), "-o", "file"],
        &[],
    );
    assert_eq!(run.code, 2);
    assert_eq!(std::fs::read_to_string(dir.join("file")).unwrap(), "x");
}

#[test]
fn a_site_is_written_and_written_again() {
    let dir = TempDir::new("web-site");
    let seed = repo_path("scenes/seed.toml");
    for _ in 0..2 {
        let run = run_kdray(
            &dir.path,
            &["web", seed.to_str().unwrap(), "-o", "site"],
            &[],
        );
        assert_eq!(run.code, 0, "{}", run.stderr_text());
    }
    let site = dir.join("site");
    for (name, _) in kdray::web::site::PAGE_FILES {
        assert!(site.join(name).is_file(), "{name}");
    }
    let kernel = std::fs::read_to_string(site.join("kernel.wgsl")).unwrap();
    assert_eq!(
        kernel,
        kdray::gpu::shaders::trace_source(kdray::gpu::bindings::UNSPLIT)
    );
    let leftovers: Vec<_> = std::fs::read_dir(&site)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".tmp"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
    // The bundle: its sections are the contract's, the arrays as prepared.
    let bytes = std::fs::read(site.join("scene.kdray")).unwrap();
    let sections = bundle::read_sections(&bytes).unwrap();
    let contract: serde_json::Value =
        serde_json::from_slice(&std::fs::read(site.join("contract.json")).unwrap()).unwrap();
    let mut expected = vec!["scene".to_string(), "frame_params".to_string()];
    expected.extend(
        contract["bundle"]["scene_arrays"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_str().unwrap().to_string()),
    );
    let names: Vec<String> = sections.iter().map(|(n, _)| n.clone()).collect();
    assert_eq!(names, expected);
    let scene = kdray::scene::load_scene(&seed).unwrap();
    let prepared = kdray::gpu::PreparedScene::new(scene, Accel::Kdtree);
    for ((name, got), (want_name, want)) in
        sections[2..].iter().zip(prepared.arrays.whole_buffers())
    {
        assert_eq!(name, want_name);
        assert_eq!(*got, want, "{name}");
    }
    assert_eq!(
        sections[1].1.len() as u64,
        contract["frame_params"]["size"].as_u64().unwrap()
    );
}

use kdray::gpu::{Accel, ArrayBindings};

#[test]
fn bad_scenes_exit_2_with_renders_error() {
    let dir = TempDir::new("web-bad");
    dir.write("bad.toml", "[camera]\nposition = [0, 0, 1]\n");
    let web = run_kdray(&dir.path, &["web", "bad.toml", "-o", "site"], &[]);
    let render = run_kdray(&dir.path, &["render", "bad.toml", "-o", "x.png"], &[]);
    assert_eq!(web.code, 2);
    assert_eq!(web.one_error_line(), render.one_error_line());
    assert!(!dir.join("site").exists(), "nothing written");
}

/// The kernel overrides of a page pipeline as web/tracer.js makes them:
/// the bundle's scene overrides and the contract's choices of `walk`,
/// `costs`, `integrator` and `entry`; with the optional bindings' needs.
fn page_pipeline(
    info: &serde_json::Value,
    contract: &serde_json::Value,
    (walk, costs, integrator, entry): (&str, bool, &str, &str),
) -> (BTreeMap<String, f64>, BTreeSet<String>) {
    let mut constants: BTreeMap<String, f64> = info["overrides"]
        .as_object()
        .expect("the bundle's overrides")
        .iter()
        .map(|(n, v)| (n.clone(), v.as_f64().unwrap()))
        .collect();
    let mut needs: BTreeSet<String> = info["needs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n.as_str().unwrap().to_string())
        .collect();
    let choices = &contract["pipeline_choices"];
    let costs = if costs { "on" } else { "off" };
    for (choice, value) in [
        ("walk", walk),
        ("costs", costs),
        ("integrator", integrator),
        ("entry", entry),
    ] {
        let made = &choices[choice][value];
        assert!(made.is_object(), "the contract has no {choice} {value}");
        for (name, v) in made["overrides"].as_object().unwrap() {
            let old = constants.insert(name.clone(), v.as_f64().unwrap());
            assert!(old.is_none(), "{name} set twice");
        }
        needs.extend(
            made["needs"]
                .as_array()
                .unwrap()
                .iter()
                .map(|n| n.as_str().unwrap().to_string()),
        );
    }
    (constants, needs)
}

/// The native host's pipeline for the same choices: the uploaded scene's
/// variant with the walk, costs and integrator, as the window's
/// accumulation and the inspector make theirs (and for the denoiser's
/// `features`, as `render --denoise` makes its radiance and feature
/// output); with the needs it reads.
fn native_pipeline(
    buffers: &kdray::gpu::SceneBuffers,
    (walk, costs, integrator, entry): (&str, bool, &str, &str),
) -> (BTreeMap<String, f64>, BTreeSet<String>) {
    use kdray::choice::Choice;
    use kdray::gpu::kernel_variant::Walk;
    use kdray::gpu::KernelVariant;
    let walk = match walk {
        "brute" => Walk::Brute,
        t => Walk::Kdtree(kdray::kdtree::Traversal::from_name(t).unwrap()),
    };
    let integrator = match integrator {
        "whitted" => kdray::layout::INTEGRATOR_WHITTED,
        _ => kdray::layout::INTEGRATOR_PATH,
    };
    let variant = KernelVariant {
        walk,
        count_costs: costs,
        integrator,
        radiance_output: entry == "features",
        feature_output: entry == "features",
        ..KernelVariant::for_scene(buffers)
    };
    let constants = variant
        .constants()
        .iter()
        .map(|(n, v)| (n.to_string(), *v))
        .collect();
    let needs = kdray::gpu::bindings::OPTIONAL_BINDINGS
        .iter()
        .filter(|(_, need)| variant.reads(*need))
        .map(|(_, need)| need.name().to_string())
        .collect();
    (constants, needs)
}

/// Every pipeline the page may make for a scene sets the kernel's
/// overrides as the native host's pipeline for the same choices does, and
/// binds what it reads: for scenes that turn on each of the scene's
/// overrides (spheres only, triangles only, glass, textures, an alpha
/// mask, vertex normals, spot and directional lights).
#[test]
fn page_pipelines_set_the_overrides_the_native_host_sets() {
    let dir = TempDir::new("web-overrides");
    let mask = r#"{"alphaMode":"MASK","pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}"#;
    let holed = image::RgbaImage::from_fn(4, 4, |x, _| image::Rgba([200, 90, 40, (x * 80) as u8]));
    common::textured::write_gltf_quad_material(
        &dir.path,
        "quad.gltf",
        mask,
        &[holed],
        Some([0.0, 0.0, 1.0]),
    );
    dir.write(
        "masked.toml",
        "[camera]\nposition = [0, 0, 3]\nlook_at = [0, 0, 0]\n\
         [[lights]]\nposition = [0, 0, 2]\n[[meshes]]\npath = \"quad.gltf\"\n",
    );
    dir.write(
        "lights.toml",
        "[camera]\nposition = [0, 5, 0]\nlook_at = [0, 0, 0]\nup = [0, 0, -1]\n\
         [materials.white]\ndiffuse = [1, 1, 1]\n\
         [[triangles]]\nvertices = [[-5, 0, -5], [5, 0, 5], [5, 0, -5]]\nmaterial = \"white\"\n\
         [[lights]]\nkind = \"spot\"\nposition = [0, 2, 0]\ndirection = [0, -1, 0]\n\
         [[lights]]\nkind = \"directional\"\ndirection = [1, -1, 0]\n",
    );
    let scenes = [
        repo_path("scenes/seed.toml"),
        repo_path("scenes/glass.toml"),
        repo_path("scenes/textured.toml"),
        dir.join("masked.toml"),
        dir.join("lights.toml"),
    ];
    let contract = kdray::web::contract::contract_json();
    let mut walks = vec!["brute"];
    walks.extend(kdray::kdtree::Traversal::ALL.map(|t| t.name()));
    // Each scene override's values over the scenes.
    let mut seen: BTreeMap<String, BTreeSet<u64>> = BTreeMap::new();
    for path in &scenes {
        let scene = kdray::scene::load_scene(path).unwrap_or_else(|e| panic!("{e}"));
        let prepared = kdray::gpu::PreparedScene::new(scene, Accel::Kdtree);
        let bytes = bundle::encode(&prepared, "scene");
        let sections = bundle::read_sections(&bytes).unwrap();
        let info: serde_json::Value = serde_json::from_slice(sections[0].1).unwrap();
        // The page binds every array whole, as this upload does.
        let buffers = kdray::gpu::SceneBuffers::upload(gpu(), &prepared.arrays)
            .unwrap_or_else(|e| panic!("{e}"));
        assert!(!buffers.split, "{path:?}");
        for (name, v) in info["overrides"].as_object().unwrap() {
            seen.entry(name.clone())
                .or_default()
                .insert(v.as_f64().unwrap() as u64);
        }
        for &walk in &walks {
            for costs in [false, true] {
                for integrator in ["whitted", "path"] {
                    for entry in ["accumulate", "inspect", "features"] {
                        let choices = (walk, costs, integrator, entry);
                        assert_eq!(
                            page_pipeline(&info, &contract, choices),
                            native_pipeline(&buffers, choices),
                            "{path:?} {choices:?}"
                        );
                    }
                }
            }
        }
    }
    for name in kdray::gpu::kernel_variant::SCENE_OVERRIDES {
        let values = &seen[name];
        let want: &[u64] = if name == "SPLIT_SCENE" { &[0] } else { &[0, 1] };
        assert!(values.iter().eq(want), "{name}: {values:?} over the scenes");
    }
}

/// What the site ships for the page's denoiser is the native denoiser's:
/// contract.json's steps are the dispatches native records its pass from
/// (`denoise::network_dispatches` of the shipped colour, albedo and
/// normal network), each convolution's block of denoise.bin holds the
/// weights native binds for that layer and group (laid out for this
/// device's alignment), the kernels are shaders/denoise/ as native compiles them,
/// the slot sizes are native's tensors and the transfer constants native's.
#[test]
fn the_site_ships_the_native_denoisers_weights_and_steps() {
    use kdray::denoise::{network_dispatches, shipped_weights, WeightsLayout, BLOCK_BYTES};
    use kdray_core::denoise::network::tensor_floats;
    use kdray_core::denoise::transfer::{pu_forward_raw, HDR_Y_MAX};
    let dir = TempDir::new("web-denoise");
    let seed = repo_path("scenes/seed.toml");
    let run = run_kdray(
        &dir.path,
        &["web", seed.to_str().unwrap(), "-o", "site"],
        &[],
    );
    assert_eq!(run.code, 0, "{}", run.stderr_text());
    let site = dir.join("site");
    let contract: serde_json::Value =
        serde_json::from_slice(&std::fs::read(site.join("contract.json")).unwrap()).unwrap();
    let spec = &contract["denoise"];
    let bin = std::fs::read(site.join(spec["weights_file"].as_str().unwrap())).unwrap();
    assert_eq!(bin.len() as u64, spec["weights_bytes"].as_u64().unwrap());

    let channels = spec["input_channels"].as_u64().unwrap() as usize;
    assert_eq!(channels, 9, "the page denoises colour, albedo and normal");
    let weights = shipped_weights(channels).unwrap();
    let align = gpu().device.limits().min_uniform_buffer_offset_alignment;
    let native = WeightsLayout::new(&weights.convs, u64::from(align)).unwrap();
    let dispatches = network_dispatches(&native.layers, channels);
    let steps = spec["steps"].as_array().unwrap();
    assert_eq!(steps.len(), dispatches.len());
    let block = BLOCK_BYTES as usize;
    let web_align = spec["weights_alignment"].as_u64().unwrap();
    for (i, (s, d)) in steps.iter().zip(&dispatches).enumerate() {
        let slot = |v: Option<kdray_core::denoise::network::Slot>| {
            v.map_or(serde_json::Value::Null, |v| format!("{v:?}").into())
        };
        assert_eq!(s["entry_point"], d.kernel.entry_point(), "dispatch {i}");
        assert_eq!(s["shader"], d.kernel.shader(), "dispatch {i}");
        assert_eq!(s["step"], d.step, "dispatch {i}");
        assert_eq!(s["level"], d.level, "dispatch {i}");
        assert_eq!(s["src"], slot(Some(d.src)), "dispatch {i}");
        assert_eq!(s["skip"], slot(d.skip), "dispatch {i}");
        assert_eq!(s["dst"], slot(Some(d.dst)), "dispatch {i}");
        assert_eq!(s["src_channels"], d.src_channels, "dispatch {i}");
        assert_eq!(s["skip_channels"], d.skip_channels, "dispatch {i}");
        assert_eq!(s["out_channels"], d.out_channels, "dispatch {i}");
        assert_eq!(s["first_output"], d.first_output, "dispatch {i}");
        assert_eq!(s["relu"], d.relu, "dispatch {i}");
        assert_eq!(s["workgroups_z"], d.workgroups(16, 16)[2], "dispatch {i}");
        // The page's workgroups along a row, from the table's columns per
        // invocation, as native counts them.
        let per = s["columns_per_invocation"].as_u64().unwrap() as usize;
        let wg = spec["workgroup"].as_u64().unwrap() as usize;
        for width in [16usize, 48, 64, 80, 1280] {
            let page = (width >> d.level).div_ceil(wg * per) as u32;
            assert_eq!(
                page,
                d.workgroups(width, 16)[0],
                "dispatch {i}, width {width}"
            );
        }
        if d.kernel == kdray::denoise::DenoiseKernel::Conv {
            let offsets = s["weights_offsets"].as_array().unwrap();
            assert_eq!(offsets.len(), 2, "dispatch {i}");
            for (half, (at, native_at)) in offsets.iter().zip(d.weights_offsets).enumerate() {
                let at = at.as_u64().unwrap();
                assert_eq!(at % web_align, 0, "dispatch {i}");
                let (at, native_at) = (at as usize, native_at as usize);
                // What conv.wgsl reads of a block: eight biases, then eight
                // weights per input channel and tap (the rest is the next
                // groups', placed by each layout's own alignment).
                let read = 4 * 8 * (1 + 9 * (d.src_channels + d.skip_channels) as usize);
                assert!(read <= block && at + block <= bin.len(), "dispatch {i}");
                assert!(
                    bin[at..at + read] == native.bytes[native_at..native_at + read],
                    "dispatch {i}, block {half}: the site's weights block differs from native's"
                );
            }
        }
    }
    // The kernels, as native compiles them.
    for (name, file, source) in kdray::web::denoise::SHADER_FILES {
        assert_eq!(spec["shaders"][name], file);
        assert_eq!(std::fs::read_to_string(site.join(file)).unwrap(), source);
    }
    // Slot sizes: a 64 x 48 tile's tensors, as native allocates them.
    let (_, per_slot) = tensor_floats(channels, 48, 64);
    let floats: Vec<f64> = spec["slot_floats_per_pixel"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap() * 64.0 * 48.0)
        .collect();
    assert_eq!(floats, per_slot.map(|f| f as f64));
    let pu_max = pu_forward_raw(HDR_Y_MAX);
    assert_eq!(spec["pu_max"].as_f64().unwrap() as f32, pu_max);
    assert_eq!(spec["pu_norm"].as_f64().unwrap() as f32, 1.0 / pu_max);
}
