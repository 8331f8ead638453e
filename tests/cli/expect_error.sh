#!/usr/bin/env bash
# expect_error.sh PATTERN COMMAND...: COMMAND must exit non-zero and print exactly one line on
# stderr that matches PATTERN (the CLI's error contract).
pattern=$1; shift
stderr=$("$@" 2>&1 >/dev/null); status=$?
if [ "$status" -eq 0 ]; then echo "expected a non-zero exit from: $*"; exit 1; fi
lines=$(printf '%s\n' "$stderr" | grep -c .)
if [ "$lines" -ne 1 ]; then echo "expected one line on stderr, got $lines:"; printf '%s\n' "$stderr"; exit 1; fi
if ! printf '%s\n' "$stderr" | grep -qE -e "$pattern"; then echo "stderr '$stderr' does not match '$pattern'"; exit 1; fi
echo "ok: $stderr"
