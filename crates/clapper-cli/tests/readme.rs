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
use std::time::Duration;

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

/// Wait for README's server to listen: it listens, or exits (a failure),
/// or the attempts (a loop bound, not a timing) run out.
fn wait_for_port(port: u16, server: &mut Child) {
    for _ in 0..6000 {
        if let Ok(Some(status)) = server.try_wait() {
            panic!("README's serve line exited ({status}) instead of serving on port {port}");
        }
        if std::net::TcpStream::connect(("127.0.0.1", port)).is_ok() {
            return;
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    panic!("README's serve line did not listen on port {port} after 6000 attempts");
}

/// A scratch folder for README's commands: `checkout/` with a copy of
/// `examples/` and an empty `docs/`, and `bin/` with `clapper` in it.
fn scratch_checkout(root: &Path) -> (tempfile::TempDir, PathBuf, PathBuf) {
    let scratch = tempfile::tempdir().unwrap();
    let dir = scratch.path().join("checkout");
    copy_dir(&root.join("examples"), &dir.join("examples"));
    std::fs::create_dir_all(dir.join("docs")).unwrap();
    let bin = scratch.path().join("bin");
    std::fs::create_dir_all(&bin).unwrap();
    std::os::unix::fs::symlink(env!("CARGO_BIN_EXE_clapper"), bin.join("clapper")).unwrap();
    (scratch, dir, bin)
}

#[test]
fn every_readme_command_line_runs_as_written() {
    let root = root();
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let lines = command_lines(&readme);
    assert!(lines.len() > 30, "found only {} command lines", lines.len());

    let (_scratch, dir, bin) = scratch_checkout(&root);

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
    let rewritten = tracked_files_written(&root, &dir);
    assert!(
        rewritten.is_empty(),
        "README's commands, run in a checkout, would rewrite tracked files: {rewritten:?}"
    );
}

/// The files under `scratch` (README's commands run there, over a copy of
/// `examples/` and an empty `docs/`) that are tracked in the checkout at
/// `root` and were written: every such file under `docs/` (it started
/// empty), and any under `examples/` whose bytes changed. Run in the
/// checkout, those commands would rewrite what git keeps.
fn tracked_files_written(root: &Path, scratch: &Path) -> Vec<String> {
    let Ok(out) = Command::new("git").args(["ls-files", "-z"]).current_dir(root).output() else {
        eprintln!("no git: tracked files not checked");
        return vec![];
    };
    if !out.status.success() {
        eprintln!("not a git checkout: tracked files not checked");
        return vec![];
    }
    let tracked: std::collections::BTreeSet<String> = String::from_utf8_lossy(&out.stdout)
        .split('\0')
        .filter(|p| !p.is_empty())
        .map(str::to_string)
        .collect();
    let mut written = vec![];
    let mut stack = vec![scratch.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
                continue;
            }
            let rel = p.strip_prefix(scratch).unwrap().to_string_lossy().replace('\\', "/");
            if !tracked.contains(&rel) {
                continue;
            }
            let changed = rel.starts_with("docs/") || std::fs::read(&p).ok() != std::fs::read(root.join(&rel)).ok();
            if changed {
                written.push(rel);
            }
        }
    }
    written.sort();
    written
}

/// README's quoted outputs (```` ```text ```` blocks) with the command
/// that prints each: the last `` `clapper ...` `` or `` `cargo run
/// --release -- ...` `` span in the prose just before the block.
fn quoted_outputs(readme: &str) -> Vec<(usize, String, Vec<String>)> {
    let lines: Vec<&str> = readme.lines().collect();
    let mut out = vec![];
    let mut i = 0;
    while i < lines.len() {
        if lines[i].trim() != "```text" {
            i += 1;
            continue;
        }
        let start = i;
        let mut block = vec![];
        i += 1;
        while i < lines.len() && lines[i].trim() != "```" {
            block.push(lines[i].to_string());
            i += 1;
        }
        // The paragraph before the block (blank lines between), joined.
        let mut end = start;
        while end > 0 && lines[end - 1].trim().is_empty() {
            end -= 1;
        }
        let mut k = end;
        while k > 0 && !lines[k - 1].trim().is_empty() {
            k -= 1;
        }
        let prose = lines[k..end].join(" ");
        let command = prose
            .split('`')
            .skip(1)
            .step_by(2)
            .filter(|c| c.starts_with("clapper ") || c.starts_with("cargo run --release -- "))
            .last()
            .unwrap_or_else(|| panic!("README:{}: a quoted output with no command before it", start + 1))
            .to_string();
        out.push((start + 1, command, block));
        i += 1;
    }
    out.extend(indented_outputs(&lines));
    out.sort_by_key(|q| q.0);
    out
}

/// README's indented quotes: an indented `cargo run --release -- ...`
/// command (continued by `\`), blank lines, then the indented block it
/// prints (indentation taken off).
fn indented_outputs(lines: &[&str]) -> Vec<(usize, String, Vec<String>)> {
    let indented = |l: &str| l.starts_with("    ");
    let mut out = vec![];
    let mut fenced = false;
    let mut i = 0;
    while i < lines.len() {
        if lines[i].trim_start().starts_with("```") {
            fenced = !fenced;
        }
        if fenced || !lines[i].starts_with("    cargo run --release -- ") || (i > 0 && indented(lines[i - 1])) {
            i += 1;
            continue;
        }
        let mut command = lines[i].trim().to_string();
        while command.ends_with('\\') && i + 1 < lines.len() {
            command.pop();
            i += 1;
            command = format!("{} {}", command.trim_end(), lines[i].trim());
        }
        i += 1;
        if i < lines.len() && indented(lines[i]) {
            continue; // more commands in the block: no output quoted
        }
        let mut k = i;
        while k < lines.len() && lines[k].trim().is_empty() {
            k += 1;
        }
        if k == i || k >= lines.len() || !indented(lines[k]) || lines[k].trim_start().starts_with("cargo run") {
            continue;
        }
        let start = k;
        let mut block = vec![];
        while k < lines.len() && (indented(lines[k]) || lines[k].trim().is_empty()) {
            block.push(lines[k].get(4..).unwrap_or("").to_string());
            k += 1;
        }
        while block.last().is_some_and(|l| l.trim().is_empty()) {
            block.pop();
        }
        out.push((start + 1, command, block));
        i = k;
    }
    out
}

/// A line as compared: a timing (`in 0.13 s on 2 threads (24472
/// strokes/s)`) is the machine's, so its figures are masked.
fn comparable(line: &str) -> String {
    let line = line.trim_end();
    let timing = line.contains("strokes/s") || (line.contains(" s on ") && line.contains(" thread"));
    if !timing {
        return line.to_string();
    }
    let mut out = String::new();
    let mut in_number = false;
    for c in line.chars() {
        if c.is_ascii_digit() || (in_number && c == '.') {
            if !in_number {
                out.push('#');
            }
            in_number = true;
        } else {
            in_number = false;
            out.push(c);
        }
    }
    out
}

/// Whether `got` is `want`, where a line `...` in `want` stands for any
/// lines; the first line that differs, if not.
fn matches_quote(want: &[String], got: &[String]) -> Result<(), String> {
    let (mut w, mut g) = (0, 0);
    while w < want.len() {
        if want[w].trim() == "..." {
            w += 1;
            let Some(next) = want.get(w) else { return Ok(()) };
            while g < got.len() && comparable(&got[g]) != comparable(next) {
                g += 1;
            }
            if g == got.len() {
                return Err(format!("README's line `{next}` is not printed"));
            }
            continue;
        }
        match got.get(g) {
            Some(line) if comparable(line) == comparable(&want[w]) => {}
            Some(line) => return Err(format!("README says\n  {}\nthe program prints\n  {}", want[w], line)),
            None => return Err(format!("README's line `{}` is not printed (output ended)", want[w])),
        }
        w += 1;
        g += 1;
    }
    if g < got.len() {
        return Err(format!("the program prints more than README quotes, from `{}`", got[g]));
    }
    Ok(())
}

/// Every output README quotes is what its command prints today (standard
/// error and output as a terminal shows them), but for timings.
#[test]
fn readme_quotes_what_the_program_prints() {
    let root = root();
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let quotes = quoted_outputs(&readme);
    assert!(quotes.len() >= 3, "found only {} quoted outputs", quotes.len());
    let (_scratch, dir, bin) = scratch_checkout(&root);
    let mut wrong = vec![];
    for (n, command, want) in &quotes {
        let out = bash(&dir, &bin, &format!("{command} 2>&1")).output().unwrap();
        assert!(out.status.success(), "README:{n}: `{command}` failed");
        let got: Vec<String> = String::from_utf8_lossy(&out.stdout)
            .lines()
            .map(str::to_string)
            .collect();
        if let Err(e) = matches_quote(want, &got) {
            wrong.push(format!("README:{n}: `{command}`: {e}"));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n\n"));
}

#[test]
fn quotes_match_with_elisions_and_timings() {
    let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    let want = s(&[
        "a",
        "  ...",
        "d",
        "  3200 strokes in 0.13 s on 2 threads (24472 strokes/s)",
    ]);
    let got = s(&[
        "a",
        "b",
        "c",
        "d",
        "  3200 strokes in 0.41 s on 1 threads (7800 strokes/s)",
    ]);
    assert!(matches_quote(&want, &got).is_ok());
    assert!(matches_quote(&want, &s(&["a", "d"])).is_err());
    assert!(matches_quote(&s(&["a", "b"]), &s(&["a", "c"])).is_err());
    assert!(matches_quote(&s(&["a"]), &s(&["a", "extra"])).is_err());
    let md = "text\n\n    cargo run --release -- x \\\n        --y 1\n\n    out 1\n      out 2\n\nmore\n\n    cargo run --release -- z\n\nprose\n";
    assert_eq!(
        quoted_outputs(md),
        vec![(
            6,
            "cargo run --release -- x --y 1".to_string(),
            vec!["out 1".to_string(), "  out 2".to_string()]
        )]
    );
    let md = "`clapper a`\n\nRun `clapper x\n--y` and `ls`\nand it prints:\n\n```text\nout\n```\n";
    assert_eq!(
        quoted_outputs(md),
        vec![(7, "clapper x --y".to_string(), vec!["out".to_string()])]
    );
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

/// The figures (`N %`, `N ms`) in `text`, in order.
fn figures(text: &str, unit: &str) -> Vec<f64> {
    let words: Vec<&str> = text.split_whitespace().collect();
    words
        .windows(2)
        .filter(|w| w[1].trim_end_matches([',', ';', ')', '.', ':']) == unit)
        .filter_map(|w| w[0].trim_start_matches(['(', '+']).parse().ok())
        .collect()
}

/// The README paragraph that starts with `start`, as one line.
fn paragraph(readme: &str, start: &str) -> String {
    let from = readme
        .find(start)
        .unwrap_or_else(|| panic!("README has no paragraph `{start}`"));
    let rest = &readme[from..];
    rest[..rest.find("\n\n").unwrap_or(rest.len())].replace('\n', " ")
}

/// Figures README quotes in its prose, not in a quoted output, are the
/// program's: the goes-up chart's agreement with the CCCBR rule (every
/// percentage the chart prints, and no other), and the odd-struckness that
/// "gaps equal to within 1 mm" allows (half the ms per mm at the ball that
/// `diagnose` prints: 1 mm of gap difference is half a mm of ball).
#[test]
fn readme_prose_figures_are_the_programs() {
    let root = root();
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let (_scratch, dir, bin) = scratch_checkout(&root);
    let run = |command: &str| {
        let out = bash(&dir, &bin, &format!("{command} 2>&1")).output().unwrap();
        assert!(out.status.success(), "`{command}` failed");
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    let printed = run("clapper chart --quantity goes-up --grid 40 --out goes-up.svg");
    let mut got = figures(&printed, "%");
    let prose = paragraph(
        &readme,
        "On the paper's plane (R = 0.2, φ_max 26°) the rule and the model agree",
    );
    let mut want = figures(&prose, "%");
    assert_eq!(got.len(), 5, "the chart prints five percentages: {printed}");
    got.sort_by(f64::total_cmp);
    want.sort_by(f64::total_cmp);
    assert_eq!(want, got, "README's goes-up figures: {prose}");

    let printed = run("clapper diagnose --preset gsm-tenor --gap-hand 253 --gap-back 247 --ball-below-pivot 0.8");
    let per_mm = printed
        .split(" ms per mm at the ball")
        .next()
        .and_then(|s| s.rsplit(' ').next())
        .and_then(|s| s.trim_start_matches('+').parse::<f64>().ok())
        .unwrap_or_else(|| panic!("no ms per mm at the ball in {printed}"));
    let prose = paragraph(&readme, "(8 ms per mm of ball movement");
    assert_eq!(figures(&prose, "ms")[0], per_mm.round(), "{prose}");
    let allowed = figures(&prose[prose.find("within 1 mm").unwrap()..], "ms")[0];
    assert_eq!(allowed, (per_mm / 2.0).round(), "1 mm of gap difference: {prose}");
}
