#!/usr/bin/env bash
# needs_file.sh FILE COMMAND...: runs COMMAND, or skips (exit 77, ctest's SKIP_RETURN_CODE) with a
# message when FILE is absent, as for the test models, which are not part of the repository.
file=$1; shift
if [ ! -f "$file" ]; then echo "skipped: $file not found (link the test models to data/models or set SPLATCL_MODELS_DIR)"; exit 77; fi
exec "$@"
