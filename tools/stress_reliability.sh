#!/usr/bin/env bash
# A bounded rerun of issue 16's stress campaign against `specula` (loopback only, 127.0.0.1;
# temporary files only; every wait is bounded; about a minute in release). It prints one
# line per check with its figures and exits 1 if any promise of README's "Reliability"
# section is broken.
#
#   cargo build --release && tools/stress_reliability.sh            # target/release/specula
#   SPECULA=target/debug/specula KILLS=3 FLIPS=10 tools/stress_reliability.sh
#
# Checks: (1) SIGKILL at random points of a measurement, each resumed: the table is
# byte-identical to an uninterrupted run; (2) a hanging `exec:` adapter after timeouts and
# restarts: no adapter process left; (3) `device serve` with a silent client connected: another
# client's hello is answered at once; (4) random byte flips in a finished journal: every
# `reconstruct --session` either refuses the file or writes the clean table; (5) an edited
# material on resume and an empty token: refused with exit 1; (6) `measure` on a hanging
# adapter whose children leave with `setsid`, stopped by kill -9, two SIGINTs or SIGTERM: no
# adapter process left 5 s after; (7) one SIGINT while the device hangs (60 s reply timeout):
# exit 130 within 5 s; (8) `device serve` with 8 hostile connections reopened (4 silent, 4
# sending 60 MB without a newline): good hellos answered within 2 s, server under 200 MiB;
# (9) a second measure through a hard link to a journal being written: refused, no `-wal`.
set -u
SPECULA=${SPECULA:-target/release/specula}
KILLS=${KILLS:-5}
FLIPS=${FLIPS:-20}
[ -x "$SPECULA" ] || { echo "no $SPECULA: build it first (cargo build --release)"; exit 2; }
work=$(mktemp -d)
trap 'kill $(jobs -p) 2>/dev/null; rm -rf "$work"' EXIT
failed=0
fail() { echo "FAIL: $*"; failed=1; }
small=(--skip-checks --grid-preset paper --probe-samples 30 --theta-h-samples 8 --theta-d-step 15 --phi-d-step 30 --seed 3)

# (1) kills at random points, then resume to the same bytes.
"$SPECULA" measure --truth silver-925 "${small[@]}" --out "$work/ref.binary" >/dev/null 2>&1 \
    || fail "reference run"
identical=0
for i in $(seq 1 "$KILLS"); do
    out="$work/kill$i.binary"
    delay_ms=$(( (RANDOM % 1500) + 50 ))
    "$SPECULA" measure --truth silver-925 "${small[@]}" --speedup 200 --out "$out" >/dev/null 2>&1 &
    pid=$!
    sleep "$(printf '0.%03d' $((delay_ms % 1000)))"; sleep $((delay_ms / 1000))
    kill -9 "$pid" 2>/dev/null; wait "$pid" 2>/dev/null
    timeout 120 "$SPECULA" measure --truth silver-925 "${small[@]}" --out "$out" >/dev/null 2>&1 \
        || fail "resume after kill $i"
    cmp -s "$out" "$work/ref.binary" && identical=$((identical + 1))
done
echo "kills: $identical of $KILLS killed runs resumed to byte-identical tables"
[ "$identical" -eq "$KILLS" ] || fail "a resumed table differs"

# (2) a hanging adapter: timeouts, restarts, then count what is left.
marker="300.$$"
timeout 60 "$SPECULA" measure --connect "exec:sleep $marker; true" \
    --calibration tools/example_adapter_calibration.toml --reply-timeout 1 --max-failures 3 \
    "${small[@]}" --out "$work/hang.binary" >/dev/null 2>&1
sleep 0.5
left=$(pgrep -fc "^sleep $marker\$" || true)
echo "hanging adapter: $left adapter processes left after 3 restarts (exit of measure: done)"
[ "$left" -eq 0 ] || fail "orphaned adapters"

# (3) a silent client does not lock out the next one.
"$SPECULA" device serve --truth silver-925 --listen 127.0.0.1:0 2>"$work/serve.log" &
server=$!
for _ in $(seq 50); do grep -q "127.0.0.1:" "$work/serve.log" && break; sleep 0.1; done
port=$(grep -o '127.0.0.1:[0-9]*' "$work/serve.log" | head -1 | cut -d: -f2)
exec 3<>"/dev/tcp/127.0.0.1/$port"   # connects and says nothing
start=$(date +%s%N)
exec 4<>"/dev/tcp/127.0.0.1/$port"
echo '{"id":1,"method":"hello","params":{"protocol":1}}' >&4
reply=""; read -r -t 10 reply <&4
ms=$(( ($(date +%s%N) - start) / 1000000 ))
exec 3>&- 4>&-
kill "$server"; wait "$server" 2>/dev/null
echo "serve: with a silent client connected, another client's hello answered in $ms ms"
case "$reply" in *'"result"'*) ;; *) fail "hello not answered: '$reply'";; esac

# (4) byte flips in a finished journal.
"$SPECULA" measure --truth silver-925 "${small[@]}" --out "$work/j.binary" >/dev/null 2>&1
"$SPECULA" reconstruct --session "$work/j.session.sqlite" --out "$work/clean.binary" >/dev/null 2>&1 \
    || fail "reconstruct of the clean journal"
refused=0; same=0
size=$(stat -c %s "$work/j.session.sqlite")
for i in $(seq 1 "$FLIPS"); do
    cp "$work/j.session.sqlite" "$work/f.sqlite"
    for _ in $(seq 200); do
        at=$(( (RANDOM * 32768 + RANDOM) % (size - 100) + 100 ))
        printf "\\x$(printf %02x $((RANDOM % 256)))" | dd of="$work/f.sqlite" bs=1 seek="$at" conv=notrunc status=none
    done
    if "$SPECULA" reconstruct --session "$work/f.sqlite" --out "$work/f.binary" >/dev/null 2>"$work/f.err"; then
        cmp -s "$work/f.binary" "$work/clean.binary" && same=$((same + 1))
    else
        [ "$(wc -l <"$work/f.err")" -eq 1 ] || fail "flip $i: not a one-line error"
        refused=$((refused + 1))
    fi
    rm -f "$work/f.sqlite-wal" "$work/f.sqlite-shm" "$work/f.binary"
done
echo "journal: $FLIPS journals with 200 random bytes overwritten: $refused refused, $same read to the clean table, $((FLIPS - refused - same)) read otherwise"
[ $((refused + same)) -eq "$FLIPS" ] || fail "a damaged journal was read into another table"

# (5) changed inputs and empty tokens.
mat="$work/mat.toml"
write_mat() { printf 'name = "mat"\n[base]\nkind = "conductor"\ndistribution = "ggx"\nalpha = %s\neta = [0.15, 0.14, 0.13]\nk = [3.9, 3.2, 2.4]\n' "$1" >"$mat"; }
write_mat 0.04
"$SPECULA" measure --truth "$mat" "${small[@]}" --out "$work/m.binary" >/dev/null 2>&1
write_mat 0.3
"$SPECULA" measure --truth "$mat" "${small[@]}" --out "$work/m.binary" >/dev/null 2>"$work/m.err"
rc=$?
echo "edited material on resume: exit $rc: $(cat "$work/m.err")"
[ "$rc" -eq 1 ] || fail "an edited material was resumed"
timeout 10 "$SPECULA" device serve --truth silver-925 --listen 0.0.0.0:0 --token '' >/dev/null 2>"$work/t.err"
rc=$?
echo "empty token: exit $rc: $(cat "$work/t.err")"
[ "$rc" -eq 1 ] || fail "an empty token was accepted"

ms_since() { echo $(( ($(date +%s%N) - $1) / 1000000 )); }
# Waits for background job $1 at most $2 s (then kills it); its exit code.
wait_bounded() {
    for _ in $(seq $(($2 * 10))); do kill -0 "$1" 2>/dev/null || break; sleep 0.1; done
    kill -KILL "$1" 2>/dev/null
    wait "$1" 2>/dev/null
}
# Processes whose command line holds the marker $1 (grep's own holds it with an escaped dot).
marked() { grep -ls -- "${1//./\\.}" /proc/[0-9]*/cmdline 2>/dev/null | wc -l; }

# (6) an adapter whose children leave with setsid, after each hard stop of measure.
report=""
for how in KILL INT2 TERM; do
    marker="900.$$0${#report}"
    "$SPECULA" measure --connect "exec:setsid sleep $marker & sleep $marker & sleep $marker" \
        --calibration tools/example_adapter_calibration.toml "${small[@]}" \
        --out "$work/a$how.binary" >/dev/null 2>&1 &
    pid=$!
    for _ in $(seq 100); do [ "$(marked "$marker")" -ge 5 ] && break; sleep 0.1; done
    start=$(date +%s%N)
    case $how in
        KILL) kill -KILL "$pid" ;;
        INT2) kill -INT "$pid"; sleep 0.05; kill -INT "$pid" 2>/dev/null ;;
        TERM) kill -TERM "$pid" ;;
    esac
    wait_bounded "$pid" 10 2>/dev/null
    ended=$(ms_since "$start")
    for _ in $(seq 50); do [ "$(marked "$marker")" -eq 0 ] && break; sleep 0.1; done
    left=$(marked "$marker")
    report="$report $how: ended in $ended ms, $left left;"
    [ "$left" -eq 0 ] && [ "$ended" -lt 5000 ] || fail "adapter after $how: $left processes left, $ended ms"
done
echo "hard stops of measure on a hanging adapter with setsid children:$report"

# (7) one SIGINT while the device hangs mid-run.
"$SPECULA" measure --connect "exec:$SPECULA device serve --truth silver-925 --seed 3 --stdio --inject-faults slow@8=1000" \
    --calibration tools/example_adapter_calibration.toml --reply-timeout 60 "${small[@]}" \
    --out "$work/hang2.binary" >/dev/null 2>"$work/hang2.err" &
pid=$!
sleep 3
start=$(date +%s%N)
kill -INT "$pid"
wait_bounded "$pid" 10 2>/dev/null; rc=$?
ms=$(ms_since "$start")
echo "one SIGINT while the device hangs (60 s reply timeout): exit $rc after $ms ms: $(tail -1 "$work/hang2.err")"
[ "$rc" -eq 130 ] && [ "$ms" -lt 5000 ] || fail "a stop waited for the hanging device"

# (8) hostile connections before authentication.
: >"$work/serve2.log"
"$SPECULA" device serve --truth silver-925 --listen 127.0.0.1:0 2>"$work/serve2.log" &
server=$!
for _ in $(seq 50); do grep -q "127.0.0.1:" "$work/serve2.log" && break; sleep 0.1; done
port=$(grep -o '127.0.0.1:[0-9]*' "$work/serve2.log" | head -1 | cut -d: -f2)
until=$(( $(date +%s) + 8 ))
hostile=()
for i in 1 2 3 4; do
    ( while [ "$(date +%s)" -lt "$until" ]; do
          exec 5<>"/dev/tcp/127.0.0.1/$port" 2>/dev/null || { sleep 0.1; continue; }
          read -r -t 5 <&5; exec 5>&-
      done ) &
    hostile+=($!)
    ( while [ "$(date +%s)" -lt "$until" ]; do
          head -c 60000000 /dev/zero 2>/dev/null >"/dev/tcp/127.0.0.1/$port"; sleep 0.05
      done ) 2>/dev/null &
    hostile+=($!)
done
sleep 1
answered=0; tries=0; slowest=0
while [ "$(date +%s)" -lt $((until - 1)) ]; do
    tries=$((tries + 1))
    start=$(date +%s%N)
    reply=""
    if exec 6<>"/dev/tcp/127.0.0.1/$port"; then
        echo '{"id":1,"method":"hello","params":{"protocol":1}}' >&6
        read -r -t 2 reply <&6
        exec 6>&-
    fi
    ms=$(ms_since "$start")
    [ "$ms" -gt "$slowest" ] && slowest=$ms
    case "$reply" in *'"result"'*) [ "$ms" -lt 2000 ] && answered=$((answered + 1));; esac
    sleep 0.3
done
wait "${hostile[@]}" 2>/dev/null
peak_kib=$(awk '/VmHWM/ {print $2}' "/proc/$server/status")
kill "$server"; wait "$server" 2>/dev/null
echo "serve under 8 hostile connections: $answered of $tries good hellos answered within 2 s (slowest $slowest ms), server peak $((peak_kib / 1024)) MiB"
[ "$answered" -eq "$tries" ] && [ "$peak_kib" -lt $((200 * 1024)) ] || fail "serve locked out or grew"

# (9) a hard link to a journal being written.
"$SPECULA" measure --truth silver-925 "${small[@]}" --speedup 0.001 --out "$work/l.binary" >/dev/null 2>&1 &
pid=$!
for _ in $(seq 100); do [ -s "$work/l.session.sqlite" ] && break; sleep 0.1; done
sleep 1
ln "$work/l.session.sqlite" "$work/h.sqlite"
"$SPECULA" measure --truth silver-925 "${small[@]}" --session "$work/h.sqlite" --out "$work/h.binary" >/dev/null 2>"$work/h.err"
rc=$?
kill "$pid"; wait "$pid" 2>/dev/null
wal=$([ -e "$work/h.sqlite-wal" ] && echo "a -wal left" || echo "no -wal left")
echo "second measure through a hard link: exit $rc, $wal: $(cat "$work/h.err")"
[ "$rc" -eq 1 ] && [ "$(wc -l <"$work/h.err")" -eq 1 ] && [ ! -e "$work/h.sqlite-wal" ] || fail "a hard link got round the lock"

# ===== Inputs and outputs: bounded reads, no panics, value ranges, output files =====
# Each check runs under a 2 GiB address-space limit and a timeout, and prints one line.
# one_line NAME CODE NEEDLE CMD...: CMD exits CODE with one short line on stderr holding NEEDLE.
one_line() {
    local name=$1 code=$2 needle=$3; shift 3
    ( ulimit -v 2097152; timeout 60 "$@" ) >/dev/null 2>"$work/io.err"
    local rc=$? lines bytes
    lines=$(wc -l <"$work/io.err"); bytes=$(wc -c <"$work/io.err")
    echo "$name: exit $rc, $lines line(s) of $bytes bytes: $(head -c 160 "$work/io.err" | tr -d '\033' | head -1)"
    [ "$rc" -eq "$code" ] && [ "$lines" -eq 1 ] && [ "$bytes" -lt 400 ] && grep -q -- "$needle" "$work/io.err" \
        && ! grep -q $'\033' "$work/io.err" || fail "$name"
}
# (I1) every read is bounded.
one_line "fit-k /dev/zero" 1 "longer than" "$SPECULA" fit-k /dev/zero
one_line "eval --dirs /dev/zero" 1 "longer than" "$SPECULA" eval silver-925 --dirs /dev/zero
one_line "reconstruct --samples-csv /dev/zero" 1 "longer than" \
    "$SPECULA" reconstruct --samples-csv /dev/zero --out "$work/z.binary"
head -c 200000000 /dev/zero | tr '\0' 'x' >"$work/header.csv"
one_line "200 MB CSV header line" 1 "longer than" "$SPECULA" fit-k "$work/header.csv"
rm -f "$work/header.csv"
one_line "token file /dev/zero" 1 "token file" \
    "$SPECULA" device serve --truth silver-925 --listen 127.0.0.1:0 --token-file /dev/zero
{ printf 'tensor_file\0\001\000\001\000\000\000\377\377'; head -c 120000 /dev/zero | tr '\0' '\033'; } >"$work/name.bsdf"
one_line "RGL field name of 65535 bytes" 1 "65535 bytes" "$SPECULA" info "$work/name.bsdf"
# (I2) no print panics.
"$SPECULA" appearance silver-925 2>"$work/pipe.err" | true
rc=${PIPESTATUS[0]}
echo "appearance | true: exit $rc, $(wc -c <"$work/pipe.err") bytes on stderr"
[ "$rc" -eq 0 ] && [ ! -s "$work/pipe.err" ] || fail "a closed pipe"
one_line "appearance > /dev/full" 1 "cannot write to standard output" \
    bash -c '"$0" appearance silver-925 >/dev/full' "$SPECULA"
write_named() { printf 'name = "%s"\n[base]\nkind = "conductor"\ndistribution = "ggx"\nalpha = 0.1\neta = [0.15, 0.14, 0.13]\nk = [3.9, 3.2, 2.4]\n' "$1" >"$work/named.toml"; }
write_named "$(head -c 65536 /dev/zero | tr '\0' 'n')"
"$SPECULA" appearance "$work/named.toml" >"$work/named.out" 2>&1
rc=$?
echo "material name of 65536 characters: exit $rc, longest output line $(awk '{ if (length > m) m = length } END { print m }' "$work/named.out") characters"
[ "$rc" -eq 0 ] || fail "a long name"
# (I3) ranges of every value read from a file.
"$SPECULA" tabulate silver-925 --out "$work/ok.binary" >/dev/null 2>&1 || fail "tabulate"
cp "$work/ok.binary" "$work/huge.binary"
printf '\240\310\353\205\363\314\341\177' | dd of="$work/huge.binary" bs=1 seek=12 conv=notrunc status=none  # 1e308
one_line "MERL table holding 1e308" 1 "above" "$SPECULA" info "$work/huge.binary"
printf '\0\0\0\0\0\0\360\277' >"$work/neg8"  # -1.0, repeated to three planes
for _ in $(seq 23); do cat "$work/neg8" "$work/neg8" >"$work/neg16"; mv "$work/neg16" "$work/neg8"; done
{ head -c 12 "$work/ok.binary"; head -c $((3 * 1458000 * 8)) "$work/neg8"; } >"$work/neg.binary"
rm -f "$work/neg8"
one_line "MERL table of negative values" 1 "no measured cell" "$SPECULA" compare "$work/neg.binary" "$work/ok.binary"
printf 'a text file, not a table\n%.0s' $(seq 100) >"$work/text.binary"
one_line "text file named .binary" 1 "not a MERL file" "$SPECULA" info "$work/text.binary"
one_line "missing input" 1 "no such file" "$SPECULA" info "$work/none.binary"
sed 's/^gain_dn_s_per_sr.*/gain_dn_s_per_sr = [1e300, 2e5, 2e5]/' tools/example_adapter_calibration.toml >"$work/cal.toml"
one_line "calibration gain 1e300" 1 "gain_dn_s_per_sr" \
    "$SPECULA" measure --connect "exec:sleep 5" --calibration "$work/cal.toml" --out "$work/c.binary"
sed 's/settle_s = 0.5 /settle_s = 1e300 /' crates/specula-acquisition/devices/utia.toml >"$work/dev.toml"
one_line "device settle_s 1e300" 1 "settle_s" "$SPECULA" plan --device "$work/dev.toml" --k 2 --out "$work/p.csv"
# (I4) output files: checked before work, never half-written.
start=$(date +%s%N)
one_line "--out naming a folder" 2 "is a directory" "$SPECULA" measure --truth silver-925 "${small[@]}" --out "$work"
echo "--out naming a folder: refused after $(( ($(date +%s%N) - start) / 1000000 )) ms"
mkdir -p "$work/fsize"
( ulimit -f 1000; "$SPECULA" tabulate silver-925 --out "$work/fsize/t.binary" ) >/dev/null 2>"$work/fsize.err"
rc=$?
left=$(find "$work/fsize" -type f | wc -l)
echo "tabulate under ulimit -f 1000: exit $rc, $(wc -l <"$work/fsize.err") line(s): $(head -1 "$work/fsize.err"); $left file(s) left"
[ "$rc" -eq 1 ] && [ "$left" -eq 0 ] && [ "$(wc -l <"$work/fsize.err")" -eq 1 ] || fail "a file-size limit"
# ===== end of the inputs and outputs checks =====

[ "$failed" -eq 0 ] && echo "all promises kept" || exit 1
