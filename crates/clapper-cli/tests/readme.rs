//! Every command line of README.md runs from the checkout as written.
//!
//! The lines are read from README's shell blocks (```` ```sh ````) and its
//! indented `cargo run` lines, and each runs in bash, in a scratch folder
//! holding a copy of `examples/` and an empty `docs/` (so outputs land
//! there, not in the checkout), with `clapper` on the PATH as the binary
//! under test and `cargo run --release --` standing for it. `serve` runs in
//! the background while the `curl` lines after it talk to it. The few
//! lines run elsewhere are named in [`ELSEWHERE`] with where.

use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// Lines (by prefix) that this test does not run, and what runs them.
const ELSEWHERE: [(&str, &str); 5] = [
    ("cargo test", "README's test command: this test is part of it"),
    ("cargo install", ".ci/run installs the binary into a scratch root"),
    ("python3 -m venv", ".ci/run makes a fresh virtual environment"),
    ("pip install", ".ci/run runs this line into a fresh virtual environment"),
    (
        "python examples/python/fig10.py",
        "the Python tests run it (crates/clapper-py/tests)",
    ),
];

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// README's command lines with their line numbers, continuation lines joined.
fn command_lines(readme: &str) -> Vec<(usize, String)> {
    let lines: Vec<&str> = readme.lines().collect();
    let mut out = vec![];
    let mut fence: Option<bool> = None; // Some(is a shell block) inside a fence
    let mut i = 0;
    while i < lines.len() {
        let l = lines[i];
        let n = i + 1;
        if let Some(info) = l.trim_start().strip_prefix("```") {
            fence = match fence {
                Some(_) => None,
                None => Some(matches!(info.trim(), "sh" | "bash")),
            };
            i += 1;
            continue;
        }
        let command = match fence {
            Some(true) => !l.trim().is_empty() && !l.trim_start().starts_with('#'),
            Some(false) => false,
            None => l.starts_with("    cargo run "),
        };
        if command {
            let mut cmd = l.trim().to_string();
            while cmd.ends_with('\\') && i + 1 < lines.len() {
                cmd.pop();
                i += 1;
                cmd.push(' ');
                cmd.push_str(lines[i].trim());
            }
            out.push((n, cmd));
        }
        i += 1;
    }
    out
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        let target = to.join(e.file_name());
        if e.file_type().unwrap().is_dir() {
            copy_dir(&e.path(), &target);
        } else {
            std::fs::copy(e.path(), target).unwrap();
        }
    }
}

/// bash running `line` with `clapper` on the PATH and `cargo run --release --`
/// standing for it.
fn bash(dir: &Path, bin: &Path, line: &str) -> Command {
    let prelude = r#"cargo() { if [ "$1 $2 $3" = "run --release --" ]; then shift 3; clapper "$@"; else echo "README test: unexpected cargo $*" >&2; return 99; fi; }"#;
    let mut c = Command::new("bash");
    c.arg("-c")
        .arg(format!("set -o pipefail\n{prelude}\n{line}"))
        .current_dir(dir)
        .env(
            "PATH",
            format!("{}:{}", bin.display(), std::env::var("PATH").unwrap_or_default()),
        )
        .env("NO_COLOR", "1");
    c
}

struct Server(Child);

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn wait_for_port(port: u16, server: &mut Child) {
    let start = Instant::now();
    while start.elapsed() < Duration::from_secs(30) {
        if let Ok(Some(status)) = server.try_wait() {
            panic!("README's serve line exited ({status}) instead of serving on port {port}");
        }
        if std::net::TcpStream::connect(("127.0.0.1", port)).is_ok() {
            return;
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    panic!("README's serve line did not listen on port {port} within 30 s");
}

#[test]
fn every_readme_command_line_runs_as_written() {
    let root = root();
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let lines = command_lines(&readme);
    assert!(lines.len() > 30, "found only {} command lines", lines.len());

    let scratch = tempfile::tempdir().unwrap();
    let dir = scratch.path().join("checkout");
    copy_dir(&root.join("examples"), &dir.join("examples"));
    std::fs::create_dir_all(dir.join("docs")).unwrap();
    let bin = scratch.path().join("bin");
    std::fs::create_dir_all(&bin).unwrap();
    std::os::unix::fs::symlink(env!("CARGO_BIN_EXE_clapper"), bin.join("clapper")).unwrap();

    let mut server: Option<Server> = None;
    let mut ran = 0;
    for (n, line) in &lines {
        if let Some((_, why)) = ELSEWHERE.iter().find(|(p, _)| line.starts_with(p)) {
            eprintln!("README:{n}: not run here ({why}): {line}");
            continue;
        }
        if line.contains(" serve") {
            let mut child = bash(&dir, &bin, line)
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .process_group(0)
                .spawn()
                .unwrap();
            wait_for_port(8080, &mut child);
            server = Some(Server(child));
            ran += 1;
            continue;
        }
        if line.starts_with("curl") {
            assert!(server.is_some(), "README:{n}: a curl line before any serve line");
        }
        let out = bash(&dir, &bin, line).output().unwrap();
        assert!(
            out.status.success(),
            "README:{n}: `{line}` failed ({}):\n{}\n{}",
            out.status,
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(
            !out.stdout.is_empty() || !out.stderr.is_empty() || line.contains("--out") || line.contains("--csv"),
            "README:{n}: `{line}` said nothing and wrote nothing asked"
        );
        ran += 1;
    }
    if let Some(Server(child)) = &server {
        // The whole group: bash and the server under it.
        let _ = Command::new("kill").arg("--").arg(format!("-{}", child.id())).status();
    }
    drop(server);
    eprintln!("ran {ran} of README's {} command lines", lines.len());
    assert!(ran + ELSEWHERE.len() >= lines.len());
}

#[test]
fn the_parser_finds_shell_blocks_and_indented_cargo_lines_only() {
    let md = "text\n```sh\nclapper a   # note\n# comment\nclapper b \\\n  --x 1\n```\n```text\nclapper c\n```\n    cargo run --release -- d\n    clapper e\n";
    let got: Vec<String> = command_lines(md).into_iter().map(|(_, c)| c).collect();
    assert_eq!(
        got,
        ["clapper a   # note", "clapper b  --x 1", "cargo run --release -- d"]
    );
}
