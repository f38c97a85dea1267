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
    use specula_session::Stage;
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
            .set_plan(Stage::Main, &(0..10).map(row).collect::<Vec<_>>())
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
        let err = journal.samples(Stage::Main).unwrap_err().to_string();
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
            let read = Journal::open_read_only(&damaged_path).and_then(|j| j.samples(Stage::Main));
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

mod serve {
    use serde_json::{json, Value};
    use specula_acquisition::instrument::{Capture, Instrument, InstrumentError, InstrumentInfo};
    use specula_acquisition::kinematics::AxisPositions;
    use specula_session::protocol::{ServeLimits, Server, Token};
    use std::io::{BufRead, BufReader, Read, Write};
    use std::net::{TcpListener, TcpStream};
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::Arc;
    use std::time::{Duration, Instant};

    /// A device that answers at once; a capture with pixels is 512 x 512 of them (~8 MB).
    struct Quick;
    impl Instrument for Quick {
        fn home(&mut self) -> Result<AxisPositions, InstrumentError> {
            Ok(AxisPositions::new(0.0, 0.0, 0.0, 0.0))
        }
        fn move_to(&mut self, target: &AxisPositions) -> Result<AxisPositions, InstrumentError> {
            Ok(*target)
        }
        fn set_light(&mut self, _: f64) -> Result<(), InstrumentError> {
            Ok(())
        }
        fn capture(
            &mut self,
            exposure_s: f64,
            with_pixels: bool,
        ) -> Result<Capture, InstrumentError> {
            let side = 512;
            Ok(Capture {
                exposure_s,
                light_level: 1.0,
                mean_raw: [100.0; 3],
                saturated_fraction: [0.0; 3],
                pixel_count: side * side,
                pixels: with_pixels.then(|| vec![[100.25f32; 3]; (side * side) as usize]),
            })
        }
        fn info(&mut self) -> Result<InstrumentInfo, InstrumentError> {
            Ok(InstrumentInfo {
                model: "quick".into(),
                serial: "1".into(),
                bit_depth: 12,
                white_level: 4095.0,
                light_levels: vec![1.0],
                exposure_range_s: (1e-5, 1.0),
            })
        }
    }

    struct Served {
        address: String,
        stop: Arc<AtomicBool>,
    }

    impl Drop for Served {
        fn drop(&mut self) {
            self.stop.store(true, Ordering::SeqCst);
        }
    }

    fn limits() -> ServeLimits {
        ServeLimits {
            idle: Duration::from_millis(1500),
            auth: Duration::from_millis(1500),
            control_wait: Duration::from_millis(300),
            write: Duration::from_millis(500),
            max_connections: 4,
            reserve: 1,
            reserve_auth: Duration::from_millis(500),
            failed_auth_pause: Duration::from_millis(300),
        }
    }

    fn serve(token: Option<&str>) -> Served {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let address = listener.local_addr().unwrap().to_string();
        let stop = Arc::new(AtomicBool::new(false));
        let flag = stop.clone();
        let token = token.map(|t| Token::new(t).unwrap());
        std::thread::spawn(move || {
            let mut server = Server::new(Box::new(Quick), "quick")
                .with_token(token)
                .with_limits(limits());
            server
                .serve_tcp(&listener, &flag, limits().idle, &mut |_| {})
                .unwrap();
        });
        Served { address, stop }
    }

    /// A client connection with a 10 s read timeout (every test stops by itself).
    struct Client {
        reader: BufReader<TcpStream>,
        writer: TcpStream,
    }

    impl Client {
        fn connect(served: &Served) -> Client {
            let stream = TcpStream::connect(&served.address).unwrap();
            stream
                .set_read_timeout(Some(Duration::from_secs(10)))
                .unwrap();
            Client {
                reader: BufReader::new(stream.try_clone().unwrap()),
                writer: stream,
            }
        }

        fn send(&mut self, request: Value) {
            writeln!(self.writer, "{request}").unwrap();
        }

        /// The next reply, or `None` when the server closed the connection.
        fn reply(&mut self) -> Option<Value> {
            let mut line = String::new();
            match self.reader.read_line(&mut line) {
                Ok(0) | Err(_) => None,
                Ok(_) => Some(serde_json::from_str(&line).unwrap()),
            }
        }

        fn hello(&mut self, token: Option<&str>) -> Option<Value> {
            let mut params = json!({"protocol": 1});
            if let Some(t) = token {
                params["token"] = json!(t);
            }
            self.send(json!({"id": 1, "method": "hello", "params": params}));
            self.reply()
        }
    }

    #[test]
    fn a_silent_connection_locks_no_one_out_and_is_closed_at_the_deadline() {
        let served = serve(None);
        let mut silent = Client::connect(&served);
        std::thread::sleep(Duration::from_millis(100));
        let started = Instant::now();
        let mut client = Client::connect(&served);
        let reply = client.hello(None).expect("answered");
        assert_eq!(reply["result"]["server"], "quick");
        assert!(
            started.elapsed() < Duration::from_secs(1),
            "{:?}",
            started.elapsed()
        );
        // The silent one never authenticated: disconnected after the 1.5 s deadline.
        let started = Instant::now();
        assert_eq!(silent.reply(), None);
        assert!(
            started.elapsed() < Duration::from_secs(3),
            "{:?}",
            started.elapsed()
        );
    }

    #[test]
    fn a_second_client_is_told_busy_and_a_dripping_controller_is_cut_off() {
        let served = serve(Some("lab"));
        let mut controller = Client::connect(&served);
        assert!(controller.hello(Some("lab")).unwrap()["result"].is_object());
        let dripping = std::thread::spawn(move || {
            // One byte every 100 ms, for up to 10 s: never a whole line.
            controller.writer.set_nonblocking(true).unwrap();
            for byte in b"{\"id\":2,\"method\":\"home\"".iter().cycle().take(100) {
                if controller.writer.write_all(&[*byte]).is_err() {
                    return true;
                }
                std::thread::sleep(Duration::from_millis(100));
                match controller.writer.peek(&mut [0u8; 1]) {
                    Ok(0) => return true,
                    Err(e) if e.kind() != std::io::ErrorKind::WouldBlock => return true,
                    _ => {}
                }
            }
            false
        });
        std::thread::sleep(Duration::from_millis(200));
        let mut other = Client::connect(&served);
        let reply = other.hello(Some("lab")).expect("a clear reply");
        assert_eq!(reply["error"]["kind"], "busy", "{reply}");
        assert_eq!(other.reply(), None, "then closed");
        assert!(dripping.join().unwrap(), "the dripping client was cut off");
        let mut other = Client::connect(&served);
        assert!(other.hello(Some("lab")).unwrap()["result"].is_object());
    }

    #[test]
    fn a_client_that_never_reads_is_cut_off_by_the_write_timeout() {
        let served = serve(None);
        let mut greedy = Client::connect(&served);
        assert!(greedy.hello(None).unwrap()["result"].is_object());
        for id in 2..8 {
            greedy.send(json!({"id": id, "method": "capture",
                               "params": {"exposure_s": 0.01, "with_pixels": true}}));
        }
        // Never read: the replies (~8 MB each) fill the socket buffers.
        let started = Instant::now();
        let mut next = loop {
            let mut client = Client::connect(&served);
            match client.hello(None) {
                Some(reply) if reply["result"].is_object() => break client,
                _ => std::thread::sleep(Duration::from_millis(100)),
            }
            assert!(
                started.elapsed() < Duration::from_secs(8),
                "still locked out"
            );
        };
        assert_eq!(next.hello(None).unwrap()["result"]["server"], "quick");
        drop(greedy);
    }

    #[test]
    fn failed_authentications_are_slowed_one_at_a_time() {
        let served = serve(Some("lab"));
        let started = Instant::now();
        let guesses: Vec<_> = (0..4)
            .map(|i| {
                let mut client = Client::connect(&served);
                std::thread::spawn(move || client.hello(Some(&format!("guess{i}"))))
            })
            .collect();
        for guess in guesses {
            let reply = guess.join().unwrap().unwrap();
            assert_eq!(reply["error"]["kind"], "unauthorized");
        }
        let elapsed = started.elapsed();
        // The first is answered at once, each next one after the pause of the one before.
        assert!(elapsed >= Duration::from_millis(3 * 300), "{elapsed:?}");
        assert!(Token::new("").is_err() && Token::new(" \n").is_err());
    }

    #[test]
    fn a_line_over_64_mib_gets_a_bad_request_reply() {
        let served = serve(None);
        let mut client = Client::connect(&served);
        let chunk = vec![b'x'; 1 << 20];
        for _ in 0..65 {
            if client.writer.write_all(&chunk).is_err() {
                break;
            }
        }
        let reply = client.reply().expect("a reply before the close");
        assert_eq!(reply["id"], Value::Null);
        assert_eq!(reply["error"]["kind"], "bad_request", "{reply}");
        let mut rest = Vec::new();
        let _ = client.reader.read_to_end(&mut rest);
    }
}

mod replies_and_inputs {
    use specula_acquisition::device::Device;
    use specula_acquisition::instrument::{Capture, Instrument, InstrumentError, InstrumentInfo};
    use specula_acquisition::kinematics::AxisPositions;
    use specula_core::materials::preset;
    use specula_core::{Brdf, GridSpec, Rgb, ThetaDSteps};
    use specula_session::pace::Paced;
    use specula_session::protocol::validate::ReplyRanges;
    use specula_session::protocol::{ClientSettings, Endpoint, RemoteInstrument, Server};
    use specula_session::workflow::{measure, MeasureOutcome, MeasureSettings, Quiet, Source};
    use std::net::TcpListener;
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::Arc;
    use std::time::{Duration, Instant};

    /// A device whose captures and moves say what the test tells it to.
    struct Liar {
        capture: Capture,
        readback: Option<AxisPositions>,
    }

    impl Instrument for Liar {
        fn home(&mut self) -> Result<AxisPositions, InstrumentError> {
            Ok(AxisPositions::new(0.0, 0.0, 0.0, 0.0))
        }
        fn move_to(&mut self, target: &AxisPositions) -> Result<AxisPositions, InstrumentError> {
            Ok(self.readback.unwrap_or(*target))
        }
        fn set_light(&mut self, _: f64) -> Result<(), InstrumentError> {
            Ok(())
        }
        fn capture(&mut self, _: f64, _: bool) -> Result<Capture, InstrumentError> {
            Ok(self.capture.clone())
        }
        fn info(&mut self) -> Result<InstrumentInfo, InstrumentError> {
            Ok(InstrumentInfo {
                model: "liar".into(),
                serial: "7".into(),
                bit_depth: 12,
                white_level: 4095.0,
                light_levels: vec![1.0, 0.1],
                exposure_range_s: (1e-5, 1.0),
            })
        }
    }

    fn good_capture() -> Capture {
        Capture {
            exposure_s: 0.01,
            light_level: 1.0,
            mean_raw: [100.0, 200.0, 300.0],
            saturated_fraction: [0.0; 3],
            pixel_count: 1849,
            pixels: None,
        }
    }

    /// Serves `instrument` named `name` on 127.0.0.1 (`port` 0: any) until `stop`.
    fn serve(instrument: Box<dyn Instrument>, name: &str, port: u16, stop: Arc<AtomicBool>) -> u16 {
        let listener = TcpListener::bind(("127.0.0.1", port)).unwrap();
        let port = listener.local_addr().unwrap().port();
        let name = name.to_string();
        std::thread::spawn(move || {
            let mut server = Server::new(instrument, name);
            server
                .serve_tcp(&listener, &stop, Duration::from_secs(20), &mut |_| {})
                .unwrap();
        });
        port
    }

    fn settings() -> ClientSettings {
        ClientSettings {
            reply_timeout: Duration::from_secs(5),
            max_failures: 3,
            backoff_initial: Duration::from_millis(1),
            ranges: ReplyRanges::for_device(&Device::utia()),
            ..ClientSettings::default()
        }
    }

    #[test]
    fn replies_outside_the_protocol_ranges_are_device_faults_naming_the_field() {
        type Spoil = Box<dyn Fn(&mut Capture)>;
        let cases: [(Spoil, &str); 4] = [
            (
                Box::new(|c| c.mean_raw[0] = 1e9),
                "mean_raw[0] = 1e9 is outside [0, 4095]",
            ),
            (
                Box::new(|c| c.mean_raw[2] = -5.0),
                "mean_raw[2] = -5 is outside",
            ),
            (
                Box::new(|c| c.saturated_fraction[1] = 1.5),
                "saturated_fraction[1] = 1.5",
            ),
            (Box::new(|c| c.mean_raw[1] = 1e308), "mean_raw[1] = 1e308"),
        ];
        for (spoil, needle) in cases {
            let mut capture = good_capture();
            spoil(&mut capture);
            let stop = Arc::new(AtomicBool::new(false));
            let liar = Liar {
                capture,
                readback: None,
            };
            let port = serve(Box::new(liar), "liar", 0, stop.clone());
            let endpoint = Endpoint::Tcp(format!("127.0.0.1:{port}"));
            let mut client = RemoteInstrument::connect(endpoint, settings()).unwrap();
            let err = client.capture(0.01, false).unwrap_err();
            let text = err.to_string();
            assert!(matches!(err, InstrumentError::CameraFault(_)), "{text}");
            assert!(
                text.contains(needle) && text.contains("127.0.0.1"),
                "{needle}: {text}"
            );
            assert!(text.contains("3 replies in a row"), "retried: {text}");
            stop.store(true, Ordering::SeqCst);
        }
        let stop = Arc::new(AtomicBool::new(false));
        let liar = Liar {
            capture: good_capture(),
            readback: Some(AxisPositions::new(1e300, 0.0, 0.0, 0.0)),
        };
        let port = serve(Box::new(liar), "liar", 0, stop.clone());
        let endpoint = Endpoint::Tcp(format!("127.0.0.1:{port}"));
        let mut client = RemoteInstrument::connect(endpoint, settings()).unwrap();
        let err = client
            .move_to(&AxisPositions::new(0.1, 0.2, 0.3, 0.4))
            .unwrap_err();
        let text = err.to_string();
        assert!(matches!(err, InstrumentError::MotorFault(_)), "{text}");
        assert!(
            text.contains("turntable_rad = 1e300 rad is outside"),
            "{text}"
        );
        assert!(client.capture(0.01, false).is_ok(), "a good reply passes");
        stop.store(true, Ordering::SeqCst);
    }

    #[test]
    fn a_reconnection_to_another_device_is_refused() {
        let stop = Arc::new(AtomicBool::new(false));
        let liar = || {
            Box::new(Liar {
                capture: good_capture(),
                readback: None,
            })
        };
        let port = serve(liar(), "serve: silver-925", 0, stop.clone());
        let endpoint = Endpoint::Tcp(format!("127.0.0.1:{port}"));
        let mut client = RemoteInstrument::connect(endpoint, settings()).unwrap();
        client.home().unwrap();
        stop.store(true, Ordering::SeqCst);
        std::thread::sleep(Duration::from_millis(200));
        let other = Arc::new(AtomicBool::new(false));
        serve(liar(), "serve: chrome", port, other.clone());
        let err = client.home().unwrap_err().to_string();
        assert!(
            err.contains("reconnected to another device")
                && err.contains("silver-925")
                && err.contains("chrome"),
            "{err}"
        );
        other.store(true, Ordering::SeqCst);
    }

    /// A BRDF under another name (as a file of the same name with other contents).
    struct Named(Arc<dyn Brdf>);

    impl Brdf for Named {
        fn eval(&self, wi: glam::DVec3, wo: glam::DVec3) -> Option<Rgb> {
            self.0.eval(wi, wo)
        }
        fn name(&self) -> String {
            "mat".into()
        }
    }

    fn start(
        truth: &str,
        session: &std::path::Path,
        stop: bool,
    ) -> Result<MeasureOutcome, specula_session::workflow_error::WorkflowError> {
        let settings = MeasureSettings {
            probe_samples: 30,
            grid: GridSpec {
                theta_h_samples: 8,
                theta_d: ThetaDSteps::even(15.0),
                phi_d_step_deg: 45.0,
                ..GridSpec::paper()
            },
            checks: false,
            ..MeasureSettings::default()
        };
        let truth: Arc<dyn Brdf> = Arc::new(Named(Arc::new(preset(truth).unwrap())));
        measure(
            Source::Simulated {
                truth,
                speedup: None,
            },
            &Device::utia(),
            &settings,
            None,
            session,
            &session.with_extension("binary"),
            Arc::new(AtomicBool::new(stop)),
            &mut Quiet,
        )
    }

    #[test]
    fn a_resume_with_another_truth_of_the_same_name_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let session = dir.path().join("s.sqlite");
        let outcome = start("silver-925", &session, true).unwrap();
        assert!(matches!(outcome, MeasureOutcome::Stopped { .. }));
        let err = start("chrome", &session, false).unwrap_err().to_string();
        assert!(
            err.contains("other inputs") && err.contains("truth (content sha256)"),
            "{err}"
        );
        assert!(matches!(
            start("silver-925", &session, true).unwrap(),
            MeasureOutcome::Stopped { .. }
        ));
    }

    #[test]
    fn a_slow_paced_device_stops_within_a_poll_of_the_flag() {
        let device = Device::utia();
        let stop = Arc::new(AtomicBool::new(false));
        let simulator = crate::common_simulator();
        // A millionth of real time: one move would take weeks.
        let mut paced = Paced::new(simulator, 1e-6).with_stop(stop.clone());
        let flag = stop.clone();
        std::thread::spawn(move || {
            std::thread::sleep(Duration::from_millis(200));
            flag.store(true, Ordering::SeqCst);
        });
        let started = Instant::now();
        paced.move_to(&device.park_axes()).unwrap();
        paced
            .move_to(&AxisPositions::from_degrees(10.0, 30.0, 150.0, 40.0))
            .unwrap();
        assert!(
            started.elapsed() < Duration::from_secs(2),
            "{:?}",
            started.elapsed()
        );
    }
}

/// The UTIA device simulated with silver.
fn common_simulator() -> specula_acquisition::simulator::Simulator {
    use specula_acquisition::device::Device;
    use specula_acquisition::simulator::sample::{MountedSample, Tilt};
    use specula_acquisition::simulator::{Simulator, SimulatorConfig};
    let device = Device::utia();
    let truth = std::sync::Arc::new(specula_core::materials::preset("silver-925").unwrap());
    let sample = MountedSample::new("silver-925", truth, Tilt::default());
    Simulator::new(device.clone(), sample, SimulatorConfig::new(1, &device))
}
