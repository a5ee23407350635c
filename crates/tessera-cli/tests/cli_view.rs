//! `tessera view` under a virtual X server: scripted sessions whose screenshots must equal
//! `tessera render` of the same state, with the validation layer on, a frame loop that stops
//! allocating once warm, resizes, and a clear refusal without a display.

mod common;
use common::*;
use std::path::Path;
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

/// An Xvfb server started for one test and stopped when dropped.
struct VirtualDisplay {
    server: Child,
    name: String,
}

impl VirtualDisplay {
    /// A fresh server on a display number the server picks itself (`-displayfd`), so tests
    /// running side by side never share one; `None` (the test reported as skipped) when Xvfb
    /// is not installed. `-noreset` keeps the server up between clients: by default it resets
    /// when its last client leaves, and a viewer connecting during that reset (a probe such as
    /// `xdotool search` had just left) is refused.
    fn start() -> Option<VirtualDisplay> {
        let spawned = Command::new("Xvfb")
            .args([
                "-displayfd",
                "1",
                "-screen",
                "0",
                "640x480x24",
                "-nolisten",
                "tcp",
                "-noreset",
            ])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn();
        let mut server = match spawned {
            Ok(server) => server,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                tessera_test::skip("", "Xvfb is not installed (Debian: apt-get install xvfb)");
                return None;
            }
            Err(e) => panic!("starting Xvfb: {e}"),
        };
        // The server writes its display number once it accepts connections.
        let mut number = String::new();
        let read = std::io::BufRead::read_line(
            &mut std::io::BufReader::new(server.stdout.take().expect("Xvfb stdout")),
            &mut number,
        );
        let number = number.trim();
        if read.is_err() || number.is_empty() {
            let _ = server.kill();
            let status = server.wait();
            panic!("Xvfb gave no display number (exit {status:?})");
        }
        Some(VirtualDisplay {
            name: format!(":{number}"),
            server,
        })
    }

    /// Runs `tessera --validation ARGS` on this display.
    fn tessera(&self, args: &[&str]) -> Output {
        Command::new(env!("CARGO_BIN_EXE_tessera"))
            .arg("--validation")
            .args(args)
            .env("DISPLAY", &self.name)
            .env_remove("WAYLAND_DISPLAY")
            .output()
            .expect("run tessera")
    }
}

impl Drop for VirtualDisplay {
    fn drop(&mut self) {
        let _ = self.server.kill();
        let _ = self.server.wait();
    }
}

/// Runs a scripted session of `data` and returns its summary line(s).
fn view(display: &VirtualDisplay, dir: &Path, data: &str, script: &str) -> String {
    let file = dir.join("script.txt");
    std::fs::write(&file, script).unwrap();
    let o = display.tessera(&["view", data, "--script", file.to_str().unwrap()]);
    let out = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(o.status.success(), "view failed: {}\n{out}", stderr(&o));
    assert!(!stderr(&o).contains("validation error"), "{}", stderr(&o));
    out
}

/// Asserts that the viewer's screenshot equals `tessera render` with `flags` at its size.
fn assert_same_as_render(shot: &Path, data: &str, flags: &[&str]) {
    let (w, h) = png_size(shot);
    let reference = shot.with_extension("render.png");
    let size = format!("{w}x{h}");
    let mut args = vec![
        "render",
        data,
        "--size",
        &size,
        "-o",
        reference.to_str().unwrap(),
    ];
    args.extend_from_slice(flags);
    let o = tessera(&args);
    assert!(o.status.success(), "render failed: {}", stderr(&o));
    // Both run the same renderer on the same device with the same state, so the images are
    // the same to the bit.
    assert!(
        png_pixels(shot) == png_pixels(&reference),
        "{} differs from `tessera render {}`",
        shot.display(),
        args.join(" ")
    );
}

/// The device allocations the summary reports after the warm-up frame and the last one.
fn allocations(summary: &str) -> (u64, u64, u64) {
    let line = summary
        .lines()
        .find(|l| l.contains("device allocations"))
        .unwrap_or_else(|| panic!("no allocation counts in: {summary}"));
    let numbers: Vec<u64> = line
        .split(|c: char| !c.is_ascii_digit())
        .filter_map(|w| w.parse().ok())
        .collect();
    // "view: F frames; device allocations after frame 5: A, after frame N: B"
    let [_, 5, warm, frames, last] = numbers[..] else {
        panic!("unexpected summary: {line}")
    };
    (warm, frames, last)
}

#[test]
fn scripted_volume_session_matches_render_and_allocates_nothing_per_frame() {
    let Some(display) = VirtualDisplay::start() else {
        return;
    };
    let dir = scratch("view_volume");
    let shot = |name: &str| dir.join(name).to_str().unwrap().to_string();
    let data = "procedural:marschner-lobb:32";
    let script = format!(
        "size 96x72\ncamera 30,20,1.8\nscreenshot {}\ncamera 120,-10,2\niso-fraction 0.3\n\
         frames 12\nscreenshot {}\nsize 80x64\nscreenshot {}\n",
        shot("a.png"),
        shot("b.png"),
        shot("c.png")
    );
    let summary = view(&display, &dir, data, &script);
    let (warm, frames, last) = allocations(&summary);
    assert!(frames > 10, "{summary}");
    assert_eq!(warm, last, "the frame loop allocated: {summary}");
    assert_eq!(png_size(&dir.join("c.png")), (80, 64), "resize");
    assert_same_as_render(&dir.join("a.png"), data, &["--camera", "30,20,1.8"]);
    let turned = ["--camera", "120,-10,2", "--iso-fraction", "0.3"];
    assert_same_as_render(&dir.join("b.png"), data, &turned);
    assert_same_as_render(&dir.join("c.png"), data, &turned);
}

#[test]
fn scripted_tet_session_switches_technique_and_edits_the_transfer_function() {
    let Some(display) = VirtualDisplay::start() else {
        return;
    };
    let dir = scratch("view_tets");
    let shot = |name: &str| dir.join(name).to_str().unwrap().to_string();
    let data = "tets:box:3";
    let saved = shot("tf.txt");
    let script = format!(
        "size 96x80\ncamera 40,25,1.9\ntf hot\ndensity 6\ntf-save {saved}\nscreenshot {}\n\
         technique shell\nscreenshot {}\ntechnique interval\nframes 2\nscreenshot {}\n",
        shot("interval.png"),
        shot("shell.png"),
        shot("back.png")
    );
    view(&display, &dir, data, &script);
    let look = ["--camera", "40,25,1.9", "--tf", &saved, "--density", "6"];
    assert_same_as_render(&dir.join("interval.png"), data, &look);
    let mut shell = look.to_vec();
    shell.extend(["--technique", "shell"]);
    assert_same_as_render(&dir.join("shell.png"), data, &shell);
    // Back on the renderer kept from before the switch.
    assert_same_as_render(&dir.join("back.png"), data, &look);
}

#[test]
fn scripted_glyph_session_matches_render() {
    let Some(display) = VirtualDisplay::start() else {
        return;
    };
    let dir = scratch("view_glyph");
    let data = "param:sh-glyph:order4";
    let shot = dir.join("glyph.png");
    let script = format!(
        "size 64x64\ncamera 10,30,2.2\nscreenshot {}\n",
        shot.display()
    );
    view(&display, &dir, data, &script);
    assert_same_as_render(&shot, data, &["--camera", "10,30,2.2"]);
}

#[test]
fn view_without_a_display_says_so() {
    let o = Command::new(env!("CARGO_BIN_EXE_tessera"))
        .args(["view", "procedural:sphere:16"])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("run tessera");
    assert_fails_with(&o, &["no display", "xvfb-run -a"]);
}

#[test]
fn bad_scripts_name_the_line() {
    let dir = scratch("view_bad_script");
    let file = dir.join("bad.txt");
    std::fs::write(&file, "camera 1,2,3\nspin 90\n").unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_tessera"))
        .args([
            "view",
            "procedural:sphere:16",
            "--script",
            file.to_str().unwrap(),
        ])
        .env("DISPLAY", ":0")
        .output()
        .expect("run tessera");
    assert_fails_with(&o, &["line 2", "unknown step 'spin'"]);
}

/// Without a display, `--offscreen` runs the same script into the renderer's target: the
/// screenshot equals `render`, the frame loop allocates nothing once warm, GPU frame times
/// are reported, and a run without a script is refused.
#[test]
fn offscreen_runs_need_no_display() {
    let dir = scratch("view_offscreen");
    let shot = dir.join("shell.png");
    let file = dir.join("script.txt");
    let script = format!(
        "size 72x56\ncamera 40,25,1.9\nframes 10\ncamera 120,10,2\nframes 3\nscreenshot {}\n",
        shot.display()
    );
    std::fs::write(&file, script).unwrap();
    let run = |extra: &[&str]| {
        let mut args = vec!["--validation", "view", "tets:box:3", "--technique", "shell"];
        args.extend_from_slice(extra);
        Command::new(env!("CARGO_BIN_EXE_tessera"))
            .args(&args)
            .env_remove("DISPLAY")
            .env_remove("WAYLAND_DISPLAY")
            .output()
            .expect("run tessera")
    };
    let o = run(&["--offscreen", "--script", file.to_str().unwrap()]);
    let out = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(o.status.success(), "{}\n{out}", stderr(&o));
    let (warm, frames, last) = allocations(&out);
    assert!(frames >= 13, "{out}");
    assert_eq!(warm, last, "the frame loop allocated: {out}");
    assert!(out.contains("GPU frame time over"), "{out}");
    let look = ["--technique", "shell", "--camera", "120,10,2"];
    assert_same_as_render(&shot, "tets:box:3", &look);
    // A usage error (clap's exit status 2) naming the missing flag.
    let refused = run(&["--offscreen"]);
    assert_eq!(refused.status.code(), Some(2), "{}", stderr(&refused));
    assert!(
        stderr(&refused).contains("--script"),
        "{}",
        stderr(&refused)
    );
}

/// Waits for `child` to end, up to `limit`; kills it and fails when it does not.
fn wait_for_exit(child: &mut Child, limit: Duration, what: &str) -> std::process::ExitStatus {
    let started = Instant::now();
    loop {
        if let Some(status) = child.try_wait().expect("poll tessera") {
            return status;
        }
        if started.elapsed() > limit {
            let _ = child.kill();
            panic!("{what}: still running after {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// A person closing the window (here the window destroyed from outside with xdotool, as a
/// window manager's close does once the client ignores the request) ends the viewer: status
/// 0, its objects freed with validation clean, the frames it drew reported.
#[test]
fn closing_the_window_ends_the_run_cleanly() {
    let Some(display) = VirtualDisplay::start() else {
        return;
    };
    if Command::new("xdotool").arg("version").output().is_err() {
        tessera_test::skip(
            "",
            "xdotool is not installed (Debian: apt-get install xdotool)",
        );
        return;
    }
    let mut viewer = Command::new(env!("CARGO_BIN_EXE_tessera"))
        .args(["--validation", "view", "tets:box:3", "--size", "64x48"])
        .env("DISPLAY", &display.name)
        .env_remove("WAYLAND_DISPLAY")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start tessera view");
    // The window appears once the data is loaded and the first frame drawn.
    let started = Instant::now();
    let window = loop {
        let found = Command::new("xdotool")
            .args(["search", "--name", "tessera view"])
            .env("DISPLAY", &display.name)
            .output()
            .expect("xdotool search");
        let id = String::from_utf8_lossy(&found.stdout).trim().to_string();
        if !id.is_empty() {
            break id.lines().next().unwrap_or_default().to_string();
        }
        if let Some(status) = viewer.try_wait().expect("poll tessera") {
            let output = viewer.wait_with_output().expect("viewer output");
            panic!(
                "the viewer ended ({status}) before its window appeared: {}",
                String::from_utf8_lossy(&output.stderr)
            );
        }
        if started.elapsed() > Duration::from_secs(60) {
            let _ = viewer.kill();
            let output = viewer.wait_with_output().expect("viewer output");
            panic!(
                "no viewer window appeared in 60 s: {}",
                String::from_utf8_lossy(&output.stderr)
            );
        }
        std::thread::sleep(Duration::from_millis(100));
    };
    std::thread::sleep(Duration::from_millis(500)); // a few frames
    let closed = Command::new("xdotool")
        .args(["windowclose", &window])
        .env("DISPLAY", &display.name)
        .status()
        .expect("xdotool windowclose");
    assert!(closed.success());
    let status = wait_for_exit(&mut viewer, Duration::from_secs(30), "closed viewer");
    let output = viewer.wait_with_output().expect("viewer output");
    let (out, err) = (
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr),
    );
    assert!(status.success(), "exit {status}: {err}\n{out}");
    assert!(
        !err.contains("validation") && !err.contains("panicked"),
        "{err}"
    );
    assert!(
        out.contains("view: ") && !out.contains("view: 0 frames"),
        "{out}"
    );
}

/// A stereo pair in the viewer (each eye half the window, joined on the GPU) equals `tessera
/// render --stereo` at half the width, in a window and offscreen.
#[test]
fn stereo_pairs_match_render() {
    let dir = scratch("view_stereo");
    let data = "tets:box:3";
    let windowed = dir.join("window.png");
    let offscreen = dir.join("offscreen.png");
    let script = |shot: &Path| {
        format!(
            "size 96x48\ncamera 40,25,1.9\nstereo 0.08\nframes 2\nscreenshot {}\n",
            shot.display()
        )
    };
    let file = dir.join("offscreen.txt");
    std::fs::write(&file, script(&offscreen)).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_tessera"))
        .args([
            "--validation",
            "view",
            data,
            "--size",
            "96x48",
            "--offscreen",
        ])
        .args(["--script", file.to_str().unwrap()])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("run tessera");
    assert!(o.status.success(), "{}", stderr(&o));
    let pair = ["--camera", "40,25,1.9", "--stereo", "0.08"];
    // `render --stereo` at 48x48 writes the two 48x48 eyes side by side: 96x48.
    let check = |shot: &Path| {
        assert_eq!(png_size(shot), (96, 48));
        let reference = shot.with_extension("render.png");
        let mut args = vec!["render", data, "--size", "48x48", "-o"];
        args.push(reference.to_str().unwrap());
        args.extend(pair);
        let r = tessera(&args);
        assert!(r.status.success(), "{}", stderr(&r));
        assert!(
            png_pixels(shot) == png_pixels(&reference),
            "{} differs",
            shot.display()
        );
    };
    check(&offscreen);
    if let Some(display) = VirtualDisplay::start() {
        view(&display, &dir, data, &script(&windowed));
        check(&windowed);
    }
}
