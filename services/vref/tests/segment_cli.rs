//! `vref segment` and `vref bench segment` as a user meets them: bad input
//! is refused with exit code 2 and a message naming the file and what is
//! wrong; good input gives 16-bit label PNGs and the JSON contract.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use image::{GrayImage, ImageBuffer, Luma, RgbImage};

fn vref(args: &[&str]) -> Output {
    let config = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../config/vref.toml");
    Command::new(env!("CARGO_BIN_EXE_vref"))
        .args(args)
        .env("VREF_CONFIG", config)
        .output()
        .unwrap()
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn osd() -> PathBuf {
    let dir = vref_testkit::data("osd");
    assert!(
        dir.join("learn").is_dir(),
        "the OSD data set is missing: expected {}",
        dir.display()
    );
    dir
}

const CAMERA: &str = r#"{"fx": 525.0, "fy": 525.0, "cx": 31.5, "cy": 23.5, "width": 64, "height": 48, "depth_scale_mm": 1.0}"#;

/// A frame's files in `dir`: colour `size`, 16-bit depth `depth_size`
/// filled with `depth`.
fn frame(dir: &Path, size: (u32, u32), depth_size: (u32, u32), depth: u16) -> [String; 4] {
    let rgb = dir.join("rgb.png");
    RgbImage::new(size.0, size.1).save(&rgb).unwrap();
    let d = dir.join("depth.png");
    ImageBuffer::<Luma<u16>, Vec<u16>>::from_pixel(depth_size.0, depth_size.1, Luma([depth]))
        .save(&d)
        .unwrap();
    let camera = dir.join("camera.json");
    std::fs::write(&camera, CAMERA).unwrap();
    let out = dir.join("out.png");
    [rgb, d, camera, out].map(|p| p.to_str().unwrap().to_owned())
}

fn refused(args: &[&str], needles: &[&str]) {
    let out = vref(args);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
    let text = stderr(&out);
    for needle in needles {
        assert!(text.contains(needle), "{args:?}: `{needle}` not in {text}");
    }
}

#[test]
fn segment_has_help() {
    for args in [&["segment", "--help"][..], &["bench", "segment", "--help"]] {
        let out = vref(args);
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(out.status.success() && text.contains("Usage:"), "{text}");
    }
}

#[test]
fn sizes_that_differ_are_refused_naming_both_files() {
    let dir = tempfile::tempdir().unwrap();
    let [rgb, depth, camera, out] = frame(dir.path(), (64, 48), (64, 40), 800);
    refused(
        &[
            "segment", "--rgb", &rgb, "--depth", &depth, "--camera", &camera, "--out", &out,
        ],
        &["depth.png is 64x40", "rgb.png is 64x48"],
    );
}

#[test]
fn depth_that_is_not_16_bit_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let [rgb, depth, camera, out] = frame(dir.path(), (64, 48), (64, 48), 800);
    GrayImage::from_pixel(64, 48, Luma([80]))
        .save(&depth)
        .unwrap();
    refused(
        &[
            "segment", "--rgb", &rgb, "--depth", &depth, "--camera", &camera, "--out", &out,
        ],
        &["depth.png", "16-bit"],
    );
}

#[test]
fn intrinsics_that_are_not_finite_and_positive_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let [rgb, depth, camera, out] = frame(dir.path(), (64, 48), (64, 48), 800);
    for (text, field) in [
        (
            CAMERA.replace("\"fx\": 525.0", "\"fx\": -525.0"),
            "fx is -525",
        ),
        (CAMERA.replace("\"fy\": 525.0", "\"fy\": 0.0"), "fy is 0"),
        (
            CAMERA.replace("\"fx\": 525.0", "\"fx\": 1e999"),
            "camera.json",
        ),
        (CAMERA.replace("\"cx\": 31.5", "\"cx\": -3.0"), "cx is -3"),
    ] {
        std::fs::write(&camera, text).unwrap();
        refused(
            &[
                "segment", "--rgb", &rgb, "--depth", &depth, "--camera", &camera, "--out", &out,
            ],
            &["camera.json", field],
        );
    }
}

#[test]
fn all_depth_missing_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let [rgb, depth, camera, out] = frame(dir.path(), (64, 48), (64, 48), 0);
    refused(
        &[
            "segment", "--rgb", &rgb, "--depth", &depth, "--camera", &camera, "--out", &out,
        ],
        &["depth.png", "no depth reading"],
    );
    assert!(
        !Path::new(&out).exists(),
        "nothing is written for a refused frame"
    );
}

#[test]
fn a_folder_of_scenes_gives_a_label_png_and_an_overlay_each() {
    let osd = osd();
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    std::fs::create_dir(&data).unwrap();
    std::fs::copy(osd.join("camera.json"), data.join("camera.json")).unwrap();
    for scene in ["learn5", "learn20"] {
        let to = data.join(scene);
        std::fs::create_dir(&to).unwrap();
        for file in ["rgb.png", "depth.png", "label.png"] {
            std::fs::copy(osd.join("learn").join(scene).join(file), to.join(file)).unwrap();
        }
    }
    let (out, over) = (dir.path().join("out"), dir.path().join("over"));
    let run = vref(&[
        "segment",
        data.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--overlay",
        over.to_str().unwrap(),
        "--json",
    ]);
    assert!(run.status.success(), "{}", stderr(&run));
    let lines: Vec<serde_json::Value> = String::from_utf8_lossy(&run.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 2);
    for (line, scene) in lines.iter().zip(["learn5", "learn20"]) {
        assert_eq!(line["scene"], scene);
        assert!(line["objects"].as_u64().unwrap() >= 2, "{line}");
        let labels = image::open(out.join(format!("{scene}.png"))).unwrap();
        let labels = labels.as_luma16().expect("16-bit labels");
        assert_eq!(labels.dimensions(), (640, 480));
        let most = labels.pixels().map(|p| p.0[0]).max().unwrap();
        assert_eq!(u64::from(most), line["objects"].as_u64().unwrap());
        assert!(over.join(format!("{scene}.png")).is_file());
    }
    let bench = vref(&[
        "bench",
        "segment",
        "--dataset",
        data.to_str().unwrap(),
        "--repeats",
        "1",
        "--json",
    ]);
    assert!(bench.status.success(), "{}", stderr(&bench));
    let text = String::from_utf8_lossy(&bench.stdout);
    let summary: serde_json::Value = serde_json::from_str(text.trim()).unwrap();
    for key in [
        "images",
        "median_us",
        "p99_us",
        "overlap_f",
        "boundary_f",
        "p75",
    ] {
        assert!(summary[key].is_number(), "{key} missing: {summary}");
    }
    assert_eq!(summary["images"], 2);
    assert!(summary["overlap_f"].as_f64().unwrap() > 0.9, "{summary}");
}

/// A noisy camera's frame (the rendered headset of BOP table scene
/// 000001, eight times a Kinect's noise) is segmented for the noise it
/// shows: about its objects, where `[segmentation]` as it is (`--noise
/// config`, set for a Kinect) cuts it into fragments.
#[test]
fn segment_sets_its_thresholds_for_the_noise_a_frame_shows() {
    let scene = vref_testkit::data("bop/table/test/000001");
    assert!(
        scene.is_dir(),
        "the BOP data set is missing: {}",
        scene.display()
    );
    let dir = tempfile::tempdir().unwrap();
    let cameras: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(scene.join("scene_camera.json")).unwrap())
            .unwrap();
    let k = &cameras["1"]["cam_K"];
    let camera = serde_json::json!({
        "fx": k[0], "fy": k[4], "cx": k[2], "cy": k[5],
        "depth_scale_mm": cameras["1"]["depth_scale"].as_f64().unwrap_or(1.0),
    });
    let camera_file = dir.path().join("camera.json");
    std::fs::write(&camera_file, camera.to_string()).unwrap();
    let instances: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(scene.join("scene_gt.json")).unwrap())
            .unwrap();
    let instances = instances["1"].as_array().unwrap().len() as u64;
    let segments = |noise: &str| {
        let out = dir.path().join(format!("{noise}.png"));
        let run = vref(&[
            "segment",
            "--rgb",
            scene.join("rgb/000001.jpg").to_str().unwrap(),
            "--depth",
            scene.join("depth/000001.png").to_str().unwrap(),
            "--camera",
            camera_file.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--noise",
            noise,
            "--json",
        ]);
        assert!(run.status.success(), "{}", stderr(&run));
        let line: serde_json::Value =
            serde_json::from_str(String::from_utf8_lossy(&run.stdout).trim()).unwrap();
        line["objects"].as_u64().unwrap()
    };
    let (measured, kinect) = (segments("frame"), segments("config"));
    assert!(
        (1..=instances + 3).contains(&measured),
        "{measured} segments for {instances} instances"
    );
    assert!(
        kinect > 2 * instances,
        "{kinect} segments for {instances} instances"
    );
}

/// `[perception] max_image_pixels` in a configuration file: checked by
/// `vref config check`, and lowered, it refuses an ordinary frame in
/// `vref segment` and `vref match`, naming the file, its size and the key.
#[test]
fn a_lowered_image_cap_refuses_a_normal_frame_naming_file_size_and_key() {
    let dir = tempfile::tempdir().unwrap();
    let [rgb, depth, camera, out] = frame(dir.path(), (64, 48), (64, 48), 800);
    let write = |name: &str, text: &str| {
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        path.to_str().unwrap().to_owned()
    };
    for (name, value) in [("zero.toml", "0"), ("huge.toml", "4294967297")] {
        let bad = write(name, &format!("[perception]\nmax_image_pixels = {value}\n"));
        refused(
            &["config", "check", &bad],
            &["perception.max_image_pixels", value],
        );
    }
    let roomy = write("roomy.toml", "[perception]\nmax_image_pixels = 3072\n");
    let out_ok = vref(&["config", "check", &roomy]);
    assert!(out_ok.status.success(), "{}", stderr(&out_ok));
    let tight = write("tight.toml", "[perception]\nmax_image_pixels = 3071\n");
    let segment = |config: &str| {
        vec![
            "segment".to_owned(),
            "--rgb".to_owned(),
            rgb.clone(),
            "--depth".to_owned(),
            depth.clone(),
            "--camera".to_owned(),
            camera.clone(),
            "--out".to_owned(),
            out.clone(),
            "--config".to_owned(),
            config.to_owned(),
        ]
    };
    let args = segment(&tight);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    refused(
        &args,
        &["rgb.png", "64x48", "3071", "[perception] max_image_pixels"],
    );
    // The same frame within the cap gets as far as segmenting (a uniform
    // depth has no objects on a plane to find, but the images were read).
    let args = segment(&roomy);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let within = vref(&args);
    assert!(
        !stderr(&within).contains("max_image_pixels"),
        "{}",
        stderr(&within)
    );
    // `vref match` on frame folders.
    let frames = dir.path().to_str().unwrap();
    refused(
        &["match", frames, frames, "--config", &tight],
        &["rgb.png", "64x48", "max_image_pixels"],
    );
}

/// A PNG whose header claims 100000 x 100000 pixels (a file of a few
/// dozen bytes) is refused from its header by `vref segment`.
#[test]
fn a_png_claiming_a_huge_size_is_refused_from_its_header() {
    let dir = tempfile::tempdir().unwrap();
    let [rgb, depth, camera, out] = frame(dir.path(), (64, 48), (64, 48), 800);
    // Signature, then an IHDR of 100000 x 100000 8-bit RGB (CRC included),
    // a one-block empty zlib stream and IEND.
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    let mut chunk = |kind: &[u8], data: &[u8]| {
        png.extend_from_slice(&(data.len() as u32).to_be_bytes());
        let mut body = kind.to_vec();
        body.extend_from_slice(data);
        let mut crc = !0u32;
        for &b in &body {
            crc ^= u32::from(b);
            for _ in 0..8 {
                crc = if crc & 1 == 1 {
                    (crc >> 1) ^ 0xEDB8_8320
                } else {
                    crc >> 1
                };
            }
        }
        png.extend_from_slice(&body);
        png.extend_from_slice(&(!crc).to_be_bytes());
    };
    let mut header = 100_000u32.to_be_bytes().to_vec();
    header.extend_from_slice(&100_000u32.to_be_bytes());
    header.extend_from_slice(&[8, 2, 0, 0, 0]);
    chunk(b"IHDR", &header);
    chunk(
        b"IDAT",
        &[0x78, 0x01, 0x01, 0x00, 0x00, 0xFF, 0xFF, 0, 0, 0, 1],
    );
    chunk(b"IEND", &[]);
    std::fs::write(&rgb, &png).unwrap();
    refused(
        &[
            "segment", "--rgb", &rgb, "--depth", &depth, "--camera", &camera, "--out", &out,
        ],
        &["rgb.png", "100000x100000", "max_image_pixels"],
    );
}
