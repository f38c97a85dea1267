//! The guardian of an `exec:` adapter (Linux): a process between Specula and the adapter
//! that ends every process the adapter started, however Specula ends.
//!
//! The adapter's command is spawned as usual, but in the forked child, before `exec`, the
//! child forks once more: the grandchild goes on to run the adapter (`sh -c COMMAND`), and
//! the child stays behind as the guardian. The guardian
//! - is a child subreaper (`PR_SET_CHILD_SUBREAPER`): every process the adapter starts, also
//!   one that calls `setsid` or forks twice to leave, stays its descendant;
//! - holds the read end of a *lifeline* pipe whose only write end is in Specula: the pipe
//!   reads end-of-file when Specula closes the link or dies in any way, `kill -9` included
//!   (so not `PR_SET_PDEATHSIG`, which fires when the spawning *thread* ends);
//! - keeps no other descriptor (not the adapter's pipes, so the link sees the adapter's end;
//!   not the journal or its lock);
//! - ignores SIGINT, SIGHUP, SIGTERM and SIGPIPE: it ends with its lifeline only (`ps`
//!   shows it as `adapter-guard`);
//! - when the lifeline closes or the adapter's shell exits, kills the adapter's process group,
//!   then every child it has (`/proc/thread-self/children`) and reaps them, over and over,
//!   until it has no child left; then it exits.
//!
//! The adapter itself dies with its guardian (`PR_SET_PDEATHSIG`), should the guardian be
//! killed. Between `fork` and `exec` only async-signal-safe calls are made (the libc
//! functions below, no allocation).

use std::os::fd::{AsRawFd, OwnedFd, RawFd};
use std::os::unix::process::CommandExt;
use std::process::{Child, Command};

/// How often the guardian looks at the adapter's shell, milliseconds.
const WATCH_MS: libc::c_int = 100;

/// The descriptor the guardian keeps its lifeline on (every other one is closed).
const LIFELINE_FD: RawFd = 3;

/// Spawns `command` under a guardian; returns the guardian (whose stdin and stdout are the
/// adapter's) and the lifeline's write end: dropping it ends the adapter and everything it
/// started.
pub(crate) fn spawn(command: &mut Command) -> std::io::Result<(Child, OwnedFd)> {
    // Both ends are close-on-exec: the adapter inherits neither.
    let (lifeline, keep_alive) = std::io::pipe()?;
    let lifeline_fd = lifeline.as_raw_fd();
    // SAFETY: the closure runs in the forked child and makes async-signal-safe calls only.
    unsafe {
        command.pre_exec(move || split(lifeline_fd));
    }
    let guardian = command.spawn()?;
    drop(lifeline);
    Ok((guardian, keep_alive.into()))
}

/// In the forked child: becomes the guardian of a grandchild that returns to run the
/// adapter's `exec`.
fn split(lifeline: RawFd) -> std::io::Result<()> {
    // SAFETY: async-signal-safe libc calls on this process's own state.
    unsafe {
        if libc::prctl(libc::PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0) != 0 {
            return Err(std::io::Error::last_os_error());
        }
        let guardian = libc::getpid();
        match libc::fork() {
            -1 => Err(std::io::Error::last_os_error()),
            0 => {
                // The adapter: its own process group, and it dies with its guardian.
                libc::setpgid(0, 0);
                libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL, 0, 0, 0);
                if libc::getppid() != guardian {
                    libc::_exit(1);
                }
                Ok(())
            }
            adapter => guard(lifeline, adapter),
        }
    }
}

/// The guardian's life: wait for the lifeline to close or the adapter's shell to exit, then
/// end every descendant and exit.
unsafe fn guard(lifeline: RawFd, adapter: libc::pid_t) -> ! {
    libc::prctl(libc::PR_SET_NAME, c"adapter-guard".as_ptr(), 0, 0, 0);
    libc::dup2(lifeline, LIFELINE_FD);
    close_all_from(LIFELINE_FD + 1);
    libc::close(libc::STDIN_FILENO);
    libc::close(libc::STDOUT_FILENO);
    for signal in [libc::SIGINT, libc::SIGHUP, libc::SIGTERM, libc::SIGPIPE] {
        libc::signal(signal, libc::SIG_IGN);
    }
    loop {
        let mut watched = [libc::pollfd {
            fd: LIFELINE_FD,
            events: libc::POLLIN,
            revents: 0,
        }];
        let ready = libc::poll(watched.as_mut_ptr(), 1, WATCH_MS);
        if ready > 0 || reap_finished(adapter) {
            break;
        }
    }
    libc::kill(-adapter, libc::SIGKILL);
    end_descendants();
    libc::_exit(0)
}

/// Closes every descriptor from `first` up.
unsafe fn close_all_from(first: RawFd) {
    #[cfg(target_env = "gnu")]
    if libc::close_range(first as libc::c_uint, libc::c_uint::MAX, 0) == 0 {
        return;
    }
    // Without close_range (another C library, a kernel before 5.9): one by one, up to the
    // descriptor limit.
    let limit = libc::sysconf(libc::_SC_OPEN_MAX).clamp(0, 1 << 20) as RawFd;
    for fd in first..limit {
        libc::close(fd);
    }
}

/// Reaps the children that have exited; true when the adapter's shell is among them.
unsafe fn reap_finished(adapter: libc::pid_t) -> bool {
    let mut adapter_ended = false;
    loop {
        let mut status = 0;
        let pid = libc::waitpid(-1, &mut status, libc::WNOHANG);
        if pid <= 0 {
            return adapter_ended;
        }
        adapter_ended |= pid == adapter;
    }
}

/// Kills and reaps children until none is left: an orphan of a killed process becomes the
/// guardian's child (it is a subreaper) before its parent can be reaped, so it is listed and
/// killed in the next round. Without the list (no `/proc`) the process group's end must do.
unsafe fn end_descendants() {
    while kill_children() {
        let mut status = 0;
        if libc::waitpid(-1, &mut status, 0) < 0
            && std::io::Error::last_os_error().raw_os_error() != Some(libc::EINTR)
        {
            return; // ECHILD: no child left
        }
    }
}

/// Sends SIGKILL to every child listed in `/proc/thread-self/children` (the guardian has one
/// thread); false when the list cannot be read.
unsafe fn kill_children() -> bool {
    let fd = libc::open(
        c"/proc/thread-self/children".as_ptr(),
        libc::O_RDONLY | libc::O_CLOEXEC,
    );
    if fd < 0 {
        return false;
    }
    let mut buffer = [0u8; 4096];
    let mut pid: libc::pid_t = 0;
    let mut digits = false;
    loop {
        let read = libc::read(fd, buffer.as_mut_ptr().cast(), buffer.len());
        let Ok(read @ 1..) = usize::try_from(read) else {
            break;
        };
        for &byte in &buffer[..read] {
            if byte.is_ascii_digit() {
                pid = pid
                    .saturating_mul(10)
                    .saturating_add(libc::pid_t::from(byte - b'0'));
                digits = true;
            } else if digits {
                libc::kill(pid, libc::SIGKILL);
                (pid, digits) = (0, false);
            }
        }
    }
    if digits {
        libc::kill(pid, libc::SIGKILL);
    }
    libc::close(fd);
    true
}
