//! Long runs of the binary: no progress noise on a stderr that is not a terminal, and Ctrl-C
//! stops a run with status 130, leaving neither its output nor a temporary file.

use sonarmap::log::{load_run, save_run};
use sonarmap::run::Run;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The building asset.
fn building() -> Run {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/building.log.json");
    load_run(&std::fs::read(path).unwrap(), "building").unwrap()
}

/// Writes `run` as a log in `dir` and returns its path.
fn write_log(dir: &Path, name: &str, run: &Run) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, save_run(run)).unwrap();
    path
}

/// The names of the files in `dir`, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn a_long_run_without_a_terminal_prints_no_progress() {
    let dir = tempfile::tempdir().unwrap();
    let log = write_log(
        dir.path(),
        "laps.log.json",
        &sonarmap::sim::repeat_laps(&building(), 3_000),
    );
    let out = Command::new(env!("CARGO_BIN_EXE_sonarmap"))
        .args(["run", log.to_str().unwrap(), "--out-map"])
        .arg(dir.path().join("laps.map.json"))
        .stdin(Stdio::null())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    // A sonarmap log is read without a note: the whole of stderr would be progress.
    assert_eq!(String::from_utf8_lossy(&out.stderr), "");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.starts_with("snapshots 3000,"), "{stdout}");
    assert!(
        !stdout.contains('\r') && !stdout.contains('\u{1b}'),
        "{stdout:?}"
    );
}

#[test]
fn ctrl_c_stops_a_run_with_130_and_leaves_no_file() {
    let dir = tempfile::tempdir().unwrap();
    // A standing robot in `paper`: every step dearer than the last, far longer than the wait.
    let mut standing = building();
    let first = standing.snapshots[0].clone();
    standing.snapshots = (0..20_000)
        .map(|i| sonarmap::run::Snapshot {
            t: i as f64,
            ..first.clone()
        })
        .collect();
    let log = write_log(dir.path(), "standing.log.json", &standing);
    let out_dir = dir.path().join("out");
    std::fs::create_dir(&out_dir).unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_sonarmap"))
        .args([
            "run",
            log.to_str().unwrap(),
            "--preset",
            "paper",
            "--out-map",
        ])
        .arg(out_dir.join("standing.map.json"))
        .arg("--out-trace")
        .arg(out_dir.join("standing.trace.json"))
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_secs(2));
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let started = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if started.elapsed() > Duration::from_secs(60) {
            child.kill().unwrap();
            panic!("the run went on after Ctrl-C");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "{stderr}");
    // (After the warning of a `paper` run whose steps keep getting dearer, when it came.)
    assert_eq!(stderr.lines().last(), Some("interrupted"), "{stderr}");
    assert!(out.stdout.is_empty());
    assert!(names(&out_dir).is_empty(), "{:?}", names(&out_dir));
}
