#!/usr/bin/env bash
# What a reviewer runs before merging: formatting, lints, docs and every test tier, as CI
# runs them. scripts/test.sh runs them all now (the lints through scripts/lint.sh).
set -euo pipefail
exec "$(dirname "$0")/test.sh" "$@"
