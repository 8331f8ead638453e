# Shared by the batch CLI tests: tiny meshes and small parameters, so each test takes seconds.
# Usage: . cli_common.sh SPLATCL WORKDIR
set -u
splatcl=$1
work=$2
rm -rf "$work" && mkdir -p "$work/meshes"
fail() { echo "FAIL: $*"; exit 1; }

cube='v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 3 4 8 7
f 2 3 7 6
f 1 5 8 4'
wedge='v 0 0 0
v 2 0 0
v 0 1 0
v 0 0 1
f 1 3 2
f 1 2 4
f 1 4 3
f 2 3 4'
# The cube with texture coordinates (every face maps the whole image), for textured splats.
textured_cube="$(printf '%s\n' "$cube" | grep '^v ')
vt 0 0
vt 1 0
vt 1 1
vt 0 1
$(printf '%s\n' "$cube" | grep '^f ' | sed -E 's|^f ([0-9]+) ([0-9]+) ([0-9]+) ([0-9]+)$|f \1/1 \2/2 \3/3 \4/4|')"

# The ids and statuses of a summary's models, in id order (only model entries carry these keys).
statuses() { grep -E '"(id|status)": ' "$1"; }
