#!/usr/bin/env bash
# The "may not" column of the crate table in docs/ARCHITECTURE.md, checked with `cargo tree`:
# one line per rule. A rule names a package and a pattern of crate names that its normal
# dependency tree (`-e normal`: not dev- or build-dependencies) may not contain, with the
# table's reason. What `cargo tree` cannot see (where `unsafe` may appear, unwinding across the
# C boundary) is checked by the compiler's lints and the tests instead.
#   bash .ci/crate-rules.sh
set -euo pipefail
cd "$(dirname "$0")/.."

failed=0

# forbid PACKAGE PATTERN WHY: PACKAGE's normal tree holds no crate whose name matches PATTERN
# (an extended regular expression for the whole name).
forbid() {
    local package=$1 pattern=$2 why=$3 found
    found=$(cargo tree -p "$package" -e normal --prefix none --quiet |
        awk '{print $1}' | grep -v -x -- "$package" | grep -E -x -- "$pattern" | sort -u || true)
    if [ -n "$found" ]; then
        echo "FAIL $package depends on $(echo "$found" | tr '\n' ' ')- $why"
        failed=1
    else
        echo "ok   $package: $why"
    fi
}

system='libc|pnet.*|iceoryx2.*|thread-priority|core_affinity|memmap2|tracing-subscriber|procimg-shm-layout'
forbid procimg-profinet "$system|procimg-.*" \
    "the protocol crate is sans-IO: no system, shared-memory or RT crate, no other procimg crate"
forbid procimg-shm-layout 'procimg-.*|serde_json' \
    "the shared-memory layout depends on no procimg crate (the control protocol sits above it)"
forbid procimg-control 'procimg-runtime|procimg-client|procimg-profinet|procimg-nic|iceoryx2' \
    "the control protocol depends on neither the daemon, the client, the protocol crate nor iceoryx2 itself (its traits for shared-memory types only)"
forbid procimg-rt-alloc 'procimg-.*|iceoryx2.*' "the real-time allocator depends on no procimg crate and not on iceoryx2"
forbid procimg-nic 'procimg-runtime' "procimg-nic does not depend on the runtime"
forbid procimg-config 'procimg-runtime|procimg-profinet|procimg-nic|iceoryx2.*|libc|pnet.*|memmap2' \
    "the configuration depends on no runtime, protocol, network, iceoryx2 or system crate"
forbid procimg-client 'procimg-runtime|procimg-profinet|procimg-nic|procimg-config' \
    "the client speaks the shared-memory layout only, not the daemon's crates"
forbid procimg-c 'procimg-runtime|procimg-profinet|procimg-nic|procimg-config' \
    "the C library is the Rust client's, not the daemon's"
forbid procimg-tools 'procimg-runtime' "the command line works over the client, the protocol crate and procimg-nic"
forbid procimg-testkit 'procimg-runtime' "the test kit does not depend on the runtime (its unit tests use the kit)"
forbid procimg-netns 'procimg-.*' "the namespaces and signals the soak shares with the test kit need no procimg crate"
forbid coded-enum '.+' "the codes' macro depends on nothing"
forbid procimg-agentx 'procimg-.*' \
    "the SNMP subagent serves plain data: it depends on no procimg crate"
forbid procimg-gs20 'procimg-runtime|procimg-profinet|procimg-nic' \
    "the GS20-PN host link is a client of procimgd (its crate speaks the host protocol and the client services), not part of the daemon"
forbid procimg-opcua 'procimg-runtime|procimg-profinet|procimg-nic' \
    "the OPC UA server is a client of procimgd, not part of the daemon"

# The test kit is a dev-dependency only: no other member's normal tree holds it.
members=$(cargo metadata --no-deps --format-version 1 |
    python3 -c 'import json,sys; print("\n".join(p["name"] for p in json.load(sys.stdin)["packages"]))')
for member in $members; do
    [ "$member" = procimg-testkit ] && continue
    forbid "$member" 'procimg-testkit' "the test kit is only a dev-dependency"
done

if [ "$failed" -ne 0 ]; then
    echo "a crate depends on what docs/ARCHITECTURE.md's table says it may not (above)"
    exit 1
fi
echo "every crate rule holds"
