//! The reliability promises of the driver protocol and the journal (issue 16), each tested
//! on the fault that broke it: orphaned adapters, a client locking others out, replies and
//! inputs trusted, a damaged journal. Network tests use 127.0.0.1 only; every loop is
//! bounded and every test stops by itself within seconds.

use specula_acquisition::instrument::Instrument;
use specula_session::protocol::{ClientSettings, Endpoint, RemoteInstrument};
use std::time::Duration;

/// Processes whose command line is exactly `words`, found in /proc.
fn processes_running(words: &[&str]) -> usize {
    let wanted: Vec<u8> = words
        .iter()
        .flat_map(|w| [w.as_bytes(), b"\0"].concat())
        .collect();
    std::fs::read_dir("/proc")
        .unwrap()
        .filter_map(|entry| std::fs::read(entry.ok()?.path().join("cmdline")).ok())
        .filter(|cmdline| *cmdline == wanted)
        .count()
}

#[test]
fn no_adapter_outlives_its_link_after_timeouts_and_restarts() {
    // An adapter that never answers, started by `sh -c` as a child of the shell (the shell
    // has another command after it, so it cannot exec it in its place).
    let seconds = format!("300.{}", std::process::id());
    let command = format!("sleep {seconds}; true");
    let settings = ClientSettings {
        reply_timeout: Duration::from_millis(300),
        max_failures: 3,
        backoff_initial: Duration::from_millis(1),
        ..ClientSettings::default()
    };
    let mut client = RemoteInstrument::new(Endpoint::Exec(command), settings);
    let err = client.home().unwrap_err().to_string();
    assert!(err.contains("failed 3 times"), "{err}");
    drop(client);
    // Killed processes vanish from /proc once reaped by init; give it a moment.
    let mut left = usize::MAX;
    for _ in 0..50 {
        left = processes_running(&["sleep", &seconds]);
        if left == 0 {
            break;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    assert_eq!(
        left, 0,
        "adapter processes left running after three restarts"
    );
}

mod journal_damage {
    use specula_acquisition::kinematics::AxisPositions;
    use specula_core::{HalfDiff, Rgb};
    use specula_session::journal::{Journal, JournalError, PlannedRow, SampleRecord};
    use std::path::Path;

    fn row(seq: u32) -> PlannedRow {
        PlannedRow {
            seq,
            hd: HalfDiff::from_degrees(seq as f64, 45.0, 40.0, 90.0),
            axes: AxisPositions::from_degrees(seq as f64, 10.0, 20.0, 30.0),
            predicted_s: 2.5,
        }
    }

    fn sample(seq: u32) -> SampleRecord {
        SampleRecord {
            stage: "main".into(),
            seq,
            value: Rgb::new(0.5, 0.25, 0.125),
            rate_dn_s: [1e5, 2e3, 7.0],
            sigma_dn_s: [10.0, 1.0, f64::INFINITY],
            lower_bound: false,
            readback: AxisPositions::from_degrees(seq as f64, 10.0, 20.0, 30.0),
            device_s: 3.0,
            wall_s: 0.01,
            finished_unix_s: 1.0e9,
            attempts: 1,
            captures: Vec::new(),
        }
    }

    /// A journal with a plan of 10 and 5 samples measured.
    fn journal(path: &Path) {
        let mut journal = Journal::open(path).unwrap();
        journal
            .set_plan("main", &(0..10).map(row).collect::<Vec<_>>())
            .unwrap();
        for seq in 0..5 {
            journal.record_sample(&sample(seq)).unwrap();
        }
    }

    fn edit(path: &Path, sql: &str) {
        let conn = rusqlite::Connection::open(path).unwrap();
        conn.execute_batch(sql).unwrap();
    }

    fn damaged(result: Result<Journal, JournalError>) -> String {
        match result {
            Err(e @ JournalError::Damaged { .. }) => e.to_string(),
            Err(e) => panic!("another error: {e}"),
            Ok(_) => panic!("a damaged journal was opened"),
        }
    }

    #[test]
    fn a_symlink_to_a_journal_takes_the_same_lock() {
        let dir = tempfile::tempdir().unwrap();
        let real = dir.path().join("J.sqlite");
        let link = dir.path().join("L.sqlite");
        std::os::unix::fs::symlink(&real, &link).unwrap();
        let _writer = Journal::open(&real).unwrap();
        let err = Journal::open(&link).err().expect("second writer refused");
        assert!(
            matches!(err, JournalError::Locked { .. }),
            "through the symlink: {err}"
        );
    }

    #[test]
    fn an_empty_journal_is_an_error_not_a_new_session() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.sqlite");
        journal(&path);
        std::fs::File::create(&path).unwrap(); // truncated to 0 bytes
        let err = damaged(Journal::open(&path));
        assert!(err.contains("s.sqlite") && err.contains("empty"), "{err}");
        assert_eq!(std::fs::metadata(&path).unwrap().len(), 0, "left as it was");
        damaged(Journal::open_read_only(&path));
    }

    #[test]
    fn a_changed_sample_value_is_seen_by_its_checksum() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.sqlite");
        journal(&path);
        edit(&path, "UPDATE samples SET r = 9e999 WHERE seq = 3;");
        let journal = Journal::open_read_only(&path).unwrap();
        let err = journal.samples("main").unwrap_err().to_string();
        assert!(
            err.contains("main sample 3") && err.contains("checksum"),
            "{err}"
        );
    }

    #[test]
    fn a_deleted_plan_row_or_an_orphan_sample_is_damage() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.sqlite");
        journal(&path);
        edit(
            &path,
            "PRAGMA foreign_keys = OFF; DELETE FROM plan WHERE seq = 7;",
        );
        let err = damaged(Journal::open(&path));
        assert!(err.contains("plan has 9 rows numbered up to 9"), "{err}");
        edit(
            &path,
            "PRAGMA foreign_keys = OFF; DELETE FROM plan WHERE seq >= 2;",
        );
        let err = damaged(Journal::open_read_only(&path));
        assert!(err.contains("3 samples outside the plan"), "{err}");
    }

    #[test]
    fn unreadable_text_and_flipped_bytes_read_as_damage() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.sqlite");
        journal(&path);
        edit(
            &path,
            "INSERT INTO meta (key, value) VALUES ('fit', CAST(X'7B22FF22' AS TEXT));",
        );
        let journal = Journal::open_read_only(&path).unwrap();
        let err = journal.meta::<f64>("fit").unwrap_err().to_string();
        assert!(
            err.contains("damaged") && err.contains("not UTF-8") || err.contains("unreadable"),
            "{err}"
        );
        drop(journal);
        // Bytes flipped all over the file (after its header), seeded: every open either
        // refuses the file as damaged or reads every sample it holds intact.
        let clean = std::fs::read(&path).unwrap();
        let mut refused = 0;
        for trial in 0..20u64 {
            let mut bytes = clean.clone();
            let mut state = 0x9E37_79B9_7F4A_7C15u64 ^ trial;
            for _ in 0..200 {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let at = 100 + (state >> 33) as usize % (bytes.len() - 100);
                bytes[at] ^= 1 << ((state >> 29) % 8);
            }
            let damaged_path = dir.path().join(format!("flip{trial}.sqlite"));
            std::fs::write(&damaged_path, &bytes).unwrap();
            let read = Journal::open_read_only(&damaged_path).and_then(|j| j.samples("main"));
            match read {
                Err(e) => {
                    refused += 1;
                    assert!(!e.to_string().contains('\n'), "{e}");
                }
                Ok(samples) => {
                    for (seq, s) in samples {
                        assert_eq!(
                            s.value,
                            sample(seq).value,
                            "trial {trial}: a changed value read as good"
                        );
                    }
                }
            }
        }
        assert!(refused >= 15, "only {refused} of 20 damaged files refused");
    }
}
