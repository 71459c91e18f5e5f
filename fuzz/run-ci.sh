#!/usr/bin/env bash
# SPDX-License-Identifier: MIT OR Apache-2.0
# Builds every fuzz target and runs each for a short fixed time from its seeds.
#
#   fuzz/run-ci.sh [SECONDS] [TARGET...]
#
# SECONDS per target (default: $FUZZ_SECONDS, else 8); every target unless some are named.
# Runs on the stable toolchain: RUSTC_BOOTSTRAP=1 lets it take the -Z flags cargo fuzz
# passes (AddressSanitizer, coverage instrumentation). $FUZZ_SANITIZER picks another
# sanitizer (`none` skips ASan's checks for a faster build and faster runs).
#
# A finding fails the script: libFuzzer prints the panic and its stack, and stores the input
# in fuzz/artifacts/<target>/; reproduce it from the repository root with
#   RUSTC_BOOTSTRAP=1 cargo fuzz run -O --codegen-units 16 <target> fuzz/artifacts/<target>/<file>
# New inputs that reach new code go to fuzz/corpus/<target>/ (not committed); the committed
# seeds in fuzz/seeds/ are only read.
set -euo pipefail
cd "$(dirname "$0")"

seconds="${1:-${FUZZ_SECONDS:-8}}"
shift || true
sanitizer="${FUZZ_SANITIZER:-address}"
export RUSTC_BOOTSTRAP=1
export CARGO_TERM_COLOR="${CARGO_TERM_COLOR:-never}"

if ! cargo fuzz --version >/dev/null 2>&1; then
    cargo install cargo-fuzz --locked
fi

# The longest input per target: a frame, an RPC PDU, a block list, an operation sequence, a
# GS20-PN UART stream (a few of its largest frames, 1478 bytes) or a text file, with room above
# the largest seed.
max_len() {
    case "$1" in
        frame | dcp | alarm | rpc) echo 1600 ;;
        control) echo 512 ;;
        connect | record | rta_channel | gs20 | topology) echo 4096 ;;
        controller | device | config) echo 8192 ;;
        gsdml) echo 32768 ;;
        *) echo 4096 ;;
    esac
}

# The same flags for build and run, so that `run` finds the build up to date. 16 codegen
# units: the runtime crate dominates the build and would otherwise compile on one core.
flags=(-O --codegen-units 16 --sanitizer "$sanitizer")

cargo fmt --check
start=$(date +%s)
cargo fuzz build "${flags[@]}"
echo "built in $(($(date +%s) - start)) s"

if [ "$#" -gt 0 ]; then
    targets=("$@")
else
    # Every [[bin]] but the seed writer.
    mapfile -t targets < <(cargo fuzz list | grep -vx seed_corpus)
fi

# The seeds are committed; write them if they are missing (a fresh checkout of an old
# revision, or after `rm -r fuzz/seeds` to regenerate them).
if [ ! -d seeds ]; then
    "${CARGO_TARGET_DIR:-target}/x86_64-unknown-linux-gnu/release/seed_corpus" seeds
fi

for t in "${targets[@]}"; do
    mkdir -p "corpus/$t" "seeds/$t"
    echo "== $t: ${seconds} s"
    # -timeout: an input running 10 s is a hang, reported as a finding; -rss_limit_mb and
    # -malloc_limit_mb (which follows it) make a huge allocation one too.
    # Progress lines and the recommended dictionary are left out of the log; the pipe keeps
    # cargo fuzz's status.
    if ! cargo fuzz run "${flags[@]}" "$t" "corpus/$t" "seeds/$t" -- \
        -max_total_time="$seconds" -max_len="$(max_len "$t")" -timeout=10 \
        -rss_limit_mb=2048 -print_final_stats=1 2>&1 |
        { grep -Ev '^(#[0-9]+ +(NEW|REDUCE|pulse) |	NEW_FUNC|"|###### )' || true; }; then
        echo "fuzz target $t found a problem; the input is in fuzz/artifacts/$t/"
        exit 1
    fi
done
echo "fuzzed ${#targets[@]} targets for ${seconds} s each in $(($(date +%s) - start)) s"
