//! The user guide cannot rot: every command of its `console` blocks runs here.
//!
//! Each page of `docs/book/src/` (sorted by path) runs in a fresh scratch folder with the
//! built `specula` first on `PATH` and `SPECULA_REPO` set to the repository root. Inside a
//! fenced block whose info string is `console`, every line starting with `$ ` is a command,
//! run by `bash -c` in page order; it must exit 0, or N when the line ends with `# exits N`.
//! Lines without `$ ` are the output the page shows and are not compared. The rules are on
//! the guide's own page, `docs/book/src/contributing.md`.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The guide keeps at least this many `$ specula` commands, so that a page cannot quietly
/// turn its examples into untested `text` blocks.
const MIN_SPECULA_COMMANDS: usize = 30;

/// The longest any one command may run before it counts as hung.
const COMMAND_TIMEOUT: Duration = Duration::from_secs(120);

/// One `$ ` line of a page.
#[derive(Debug, Clone, PartialEq)]
struct GuideCommand {
    /// The page, relative to the book's `src/`.
    page: PathBuf,
    /// 1-based line number in the page.
    line: usize,
    /// The shell text after `$ `, without the `# exits N` marker.
    shell: String,
    /// The exit status the page promises.
    expected_exit: i32,
}

fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn book_src() -> PathBuf {
    repo_root().join("docs/book/src")
}

/// Every Markdown file under `dir`, sorted.
fn pages(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).expect("the book's source folder is readable") {
            let path = entry.expect("a readable folder entry").path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "md") {
                out.push(path);
            }
        }
    }
    out.sort();
    out
}

/// Splits `text # exits N` into the text and N; anything else exits 0.
fn expected_exit(shell: &str) -> (String, i32) {
    if let Some((text, marker)) = shell.rsplit_once("# exits ") {
        if let Ok(code) = marker.trim().parse::<i32>() {
            return (text.trim_end().to_string(), code);
        }
    }
    (shell.to_string(), 0)
}

/// The `$ ` lines of the `console` blocks of one page.
fn commands_of(page: &Path, text: &str) -> Vec<GuideCommand> {
    let mut out = Vec::new();
    let mut in_console = false;
    let mut in_block = false;
    for (i, raw) in text.lines().enumerate() {
        let line = raw.trim_start();
        if let Some(info) = line.strip_prefix("```") {
            if in_block {
                in_block = false;
                in_console = false;
            } else {
                in_block = true;
                in_console = info.trim() == "console";
            }
            continue;
        }
        if let Some(shell) = line.strip_prefix("$ ").filter(|_| in_console) {
            let (shell, expected_exit) = expected_exit(shell);
            out.push(GuideCommand {
                page: page.strip_prefix(book_src()).unwrap_or(page).to_path_buf(),
                line: i + 1,
                shell,
                expected_exit,
            });
        }
    }
    out
}

/// Runs one command in `dir`; returns its exit status and standard error, or why it did not
/// finish.
fn run(cmd: &GuideCommand, dir: &Path, path_var: &str) -> Result<(i32, String), String> {
    let mut child = Command::new("bash")
        .arg("-c")
        .arg(&cmd.shell)
        .current_dir(dir)
        .env("PATH", path_var)
        .env(
            "SPECULA_REPO",
            repo_root()
                .canonicalize()
                .expect("the repository root exists"),
        )
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot start bash: {e}"))?;
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().map_err(|e| e.to_string())? {
            let mut stderr = String::new();
            if let Some(mut pipe) = child.stderr.take() {
                use std::io::Read;
                let _ = pipe.read_to_string(&mut stderr);
            }
            return Ok((status.code().unwrap_or(-1), stderr));
        }
        if start.elapsed() > COMMAND_TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!(
                "still running after {} s",
                COMMAND_TIMEOUT.as_secs()
            ));
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

#[test]
fn every_console_command_of_the_guide_runs_as_written() {
    let bin_dir = Path::new(env!("CARGO_BIN_EXE_specula"))
        .parent()
        .expect("the binary has a folder")
        .to_path_buf();
    let path_var = format!(
        "{}:{}",
        bin_dir.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let mut failures = Vec::new();
    let mut specula_commands = 0;
    let started = Instant::now();
    for page in pages(&book_src()) {
        let text = std::fs::read_to_string(&page).expect("a readable page");
        let commands = commands_of(&page, &text);
        if commands.is_empty() {
            continue;
        }
        let scratch = tempfile::tempdir().expect("a scratch folder");
        let page_started = Instant::now();
        for cmd in &commands {
            if cmd.shell.starts_with("specula") {
                specula_commands += 1;
            }
            match run(cmd, scratch.path(), &path_var) {
                Ok((code, _)) if code == cmd.expected_exit => {}
                Ok((code, stderr)) => failures.push(format!(
                    "{}:{}: `{}` exited {code}, the page says {}; stderr:\n{}",
                    cmd.page.display(),
                    cmd.line,
                    cmd.shell,
                    cmd.expected_exit,
                    stderr.trim_end()
                )),
                Err(why) => failures.push(format!(
                    "{}:{}: `{}` {why}",
                    cmd.page.display(),
                    cmd.line,
                    cmd.shell
                )),
            }
        }
        eprintln!(
            "{}: {} commands in {:.1} s",
            page.strip_prefix(book_src()).unwrap_or(&page).display(),
            commands.len(),
            page_started.elapsed().as_secs_f64()
        );
    }
    eprintln!(
        "{specula_commands} specula commands in {:.1} s",
        started.elapsed().as_secs_f64()
    );
    assert!(
        failures.is_empty(),
        "{} guide command(s) failed:\n{}",
        failures.len(),
        failures.join("\n")
    );
    assert!(
        specula_commands >= MIN_SPECULA_COMMANDS,
        "the guide runs {specula_commands} `$ specula` commands, at least {MIN_SPECULA_COMMANDS} expected"
    );
}

#[test]
fn console_blocks_are_read_as_the_guide_promises() {
    let page = book_src().join("example.md");
    let text = "```console\n$ specula info x # exits 1\nerror: x\n```\n\n```text\n$ specula measure\n```\n```console\n  $ echo hi\n```\n";
    let got = commands_of(&page, text);
    let want = vec![
        GuideCommand {
            page: "example.md".into(),
            line: 2,
            shell: "specula info x".into(),
            expected_exit: 1,
        },
        GuideCommand {
            page: "example.md".into(),
            line: 10,
            shell: "echo hi".into(),
            expected_exit: 0,
        },
    ];
    assert_eq!(got, want);
}
