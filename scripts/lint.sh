#!/usr/bin/env bash
# The lints CI runs before the tests (scripts/test.sh runs this first; it also runs alone):
# rustfmt's formatting, clippy with every warning an error on every target of the workspace,
# and rustdoc with every warning (a broken intra-doc link, say) an error. The lints
# themselves are Cargo.toml's ([lints]) and clippy.toml's. All three run; a failure is
# named in one line at the end and the script exits 1.
#
# clippy and rustdoc run with --release: the build scripts and procedural macros they need are
# the release build's (scripts/test.sh), and rustdoc reuses the dependencies clippy checked.
# They still check every dependency once (metadata only, no code): docs/testing.md has the
# times.
set -uo pipefail
cd "$(dirname "$0")/.."
failed=()

lint() { # NAME WHAT-A-FAILURE-MEANS COMMAND...
    local name=$1 meaning=$2 started=$SECONDS
    shift 2
    echo "== lint: $name ($*)" >&2
    if ! "$@"; then
        failed+=("$name: $meaning")
    fi
    echo "== lint: $name took $((SECONDS - started)) s" >&2
}

lint rustfmt "the code is not formatted as rustfmt formats it: \`cargo fmt --all\` formats it" \
    cargo fmt --all --check
lint clippy "clippy warned (each warning is an error here) on the code named above" \
    cargo clippy --release --workspace --all-targets -- -D warnings
lint rustdoc "rustdoc warned (a broken or ambiguous doc link, a bad code block) on the docs named above" \
    env RUSTDOCFLAGS="-D warnings" cargo doc --release --workspace --no-deps

if ((${#failed[@]})); then
    for f in "${failed[@]}"; do
        echo "lint failed: $f" >&2
    done
    exit 1
fi
echo "== lints passed" >&2
