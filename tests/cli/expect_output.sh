#!/usr/bin/env bash
# expect_output.sh CHECK... -- COMMAND...: COMMAND must exit 0 and its outputs have the properties
# the checks name (the CLI's success contract; expect_error.sh is its failure contract). Files the
# checks name are removed first, so a stale one from an earlier run cannot pass. Checks:
#   --match REGEX        a line of stdout or stderr matches REGEX (grep -E)
#   --no-match REGEX     no line does
#   --file PATH REGEX    PATH exists and a line of it matches REGEX (a text output)
#   --png PATH W H       PATH is a PNG image of W × H pixels
#   --exr PATH           PATH is an OpenEXR image
#   --ply PATH MIN       PATH is a PLY file whose first element has at least MIN entries
set -u
matches=() no_matches=() files=() file_patterns=() pngs=() png_sizes=() exrs=() plys=() ply_mins=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do
  case $1 in
    --match) matches+=("$2"); shift 2 ;;
    --no-match) no_matches+=("$2"); shift 2 ;;
    --file) files+=("$2"); file_patterns+=("$2"$'\n'"$3"); shift 3 ;;
    --png) pngs+=("$2"); png_sizes+=("$3 $4"); shift 4 ;;
    --exr) exrs+=("$2"); shift 2 ;;
    --ply) plys+=("$2"); ply_mins+=("$3"); shift 3 ;;
    *) echo "expect_output.sh: unknown check '$1'"; exit 2 ;;
  esac
done
[ "${1:-}" = "--" ] || { echo "expect_output.sh: no -- before the command"; exit 2; }
shift
for f in "${files[@]}" "${pngs[@]}" "${exrs[@]}" "${plys[@]}"; do rm -f "$f"; done
output=$("$@" 2>&1); status=$?
fail() { echo "FAIL: $*"; printf '%s\n' "$output" | tail -n 40; exit 1; }
[ "$status" -eq 0 ] || fail "exit status $status from: $*"
for m in "${matches[@]}"; do printf '%s\n' "$output" | grep -qE -e "$m" || fail "no output line matches '$m'"; done
for m in "${no_matches[@]}"; do ! printf '%s\n' "$output" | grep -qE -e "$m" || fail "an output line matches '$m'"; done
for entry in "${file_patterns[@]}"; do
  path=${entry%%$'\n'*} pattern=${entry#*$'\n'}
  [ -s "$path" ] || fail "$path was not written"
  grep -qE -e "$pattern" "$path" || fail "no line of $path matches '$pattern'"
done
for k in "${!pngs[@]}"; do
  path=${pngs[$k]}; read -r w h <<< "${png_sizes[$k]}"
  [ -s "$path" ] || fail "$path was not written"
  [ "$(head -c 8 "$path" | od -An -tx1 | tr -d ' \n')" = "89504e470d0a1a0a" ] || fail "$path is not a PNG"
  size=$(od -An -j16 -N8 -tu1 "$path" | awk '{print $1*16777216+$2*65536+$3*256+$4, $5*16777216+$6*65536+$7*256+$8}')
  [ "$size" = "$w $h" ] || fail "$path is $size pixels, not $w $h"
done
for path in "${exrs[@]}"; do
  [ -s "$path" ] || fail "$path was not written"
  [ "$(head -c 4 "$path" | od -An -tx1 | tr -d ' \n')" = "762f3101" ] || fail "$path is not an OpenEXR image"
done
for k in "${!plys[@]}"; do
  path=${plys[$k]}
  [ -s "$path" ] || fail "$path was not written"
  [ "$(head -c 4 "$path" | od -An -c | tr -d ' ')" = 'ply\n' ] || fail "$path is not a PLY file"
  count=$(head -c 4096 "$path" | grep -a -m1 '^element ' | awk '{print $3}')
  [ -n "$count" ] && [ "$count" -ge "${ply_mins[$k]}" ] || fail "$path has ${count:-no} entries in its first element, fewer than ${ply_mins[$k]}"
done
echo "ok: $*"
