//! `--help` teaches quickly: every command's help is a summary of at most
//! [`MAX_HELP_LINES`] lines that names its reference page in the guide, and that page exists.
//! The long explanations live on the page (`docs/book/src/reference/`).

use assert_cmd::Command;
use std::path::Path;

/// The most lines `specula <command> --help` may print (at clap's default width of 100
/// columns when standard output is not a terminal).
const MAX_HELP_LINES: usize = 40;

/// The help of `words` (`["check", "flare"]`), as printed.
fn help(words: &[String]) -> String {
    let out = Command::cargo_bin("specula")
        .expect("the specula binary is built")
        .args(words)
        .arg("--help")
        .env_remove("COLUMNS")
        .output()
        .expect("specula runs");
    assert!(
        out.status.success(),
        "`specula {} --help` failed",
        words.join(" ")
    );
    String::from_utf8(out.stdout).expect("help is UTF-8")
}

/// The subcommand names listed under "Commands:" of a help text (not `help`).
fn subcommands(help: &str) -> Vec<String> {
    help.lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        // A wrapped description continues deeper than the two spaces of a name.
        .filter(|l| !l.starts_with("   "))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|name| *name != "help")
        .map(str::to_string)
        .collect()
}

/// Every command path reachable from `specula`, the top level included.
fn all_commands() -> Vec<Vec<String>> {
    let mut out = Vec::new();
    let mut todo = vec![Vec::<String>::new()];
    while let Some(words) = todo.pop() {
        for sub in subcommands(&help(&words)) {
            let mut next = words.clone();
            next.push(sub);
            todo.push(next);
        }
        out.push(words);
    }
    out.sort();
    out
}

#[test]
fn every_help_is_a_short_summary_linking_its_reference_page() {
    let book = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/book/src");
    let commands = all_commands();
    assert!(
        commands.len() > 20,
        "found only {} commands",
        commands.len()
    );
    let mut problems = Vec::new();
    for words in &commands {
        let text = help(words);
        let name = format!("specula {}", words.join(" "))
            .trim_end()
            .to_string();
        let lines = text.lines().count();
        if lines > MAX_HELP_LINES {
            problems.push(format!(
                "`{name} --help` has {lines} lines (at most {MAX_HELP_LINES})"
            ));
        }
        let Some(page) = text
            .split_whitespace()
            .find(|w| w.starts_with("docs/book/src/reference/"))
        else {
            problems.push(format!("`{name} --help` names no reference page"));
            continue;
        };
        let page = page.trim_end_matches(['.', ',', ')']);
        if !book
            .join(page.trim_start_matches("docs/book/src/"))
            .is_file()
        {
            problems.push(format!(
                "`{name} --help` names {page}, which does not exist"
            ));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
