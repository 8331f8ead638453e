#!/usr/bin/env bash
# splats_3dgs_test.sh SPLATCL CUBE WORKDIR CUBE_PLY CLIP_PLY: `splatcl splats --format 3dgs` on the
# cube, read back with od and awk, knowing nothing of splatcl's writer: the header's element and
# property list exactly, the vertex count = that of the splat PLY the same parameters gave
# (CUBE_PLY, CLIP_PLY: cli.splats_cube and cli.splats_clip), the body size, and per Gaussian a unit
# quaternion whose rotation of z is the stored normal, a unit normal, σ_n < σ_v ≤ σ_u,
# sigmoid(opacity) = 0.99 and colours in [0, 1]. Then --clip: the same checks, and one warning line
# giving the clipped count.
set -u
splatcl=$1 cube=$2 work=$3 cube_ply=$4 clip_ply=$5
vertex_count() { grep -a -m1 '^element vertex ' "$1" | tr -dc 0-9; }
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work" && mkdir -p "$work"
out=$work/cube-3dgs.ply

"$splatcl" splats "$cube" --samples grid:8 --eps 0.002 --color-field hard --color-tol 40 --format 3dgs -o "$out" \
  2>"$work/stderr" >/dev/null || fail "splats --format 3dgs failed: $(cat "$work/stderr")"
grep -v '^splatcl: note: ' "$work/stderr" | grep -q . && fail "unexpected stderr: $(cat "$work/stderr")"
# splats verify names the export for what it is (it said "header line 3 is '...', not 'comment splatcl_version VALUE'").
if "$splatcl" splats verify "$cube" "$out" >/dev/null 2>"$work/verify.err"; then fail "verify accepted a 3DGS export"; fi
grep -q "^splatcl: splat file $out: not a splatcl splat file (no 'comment splatcl_version' in its header): a 3D Gaussian splatting PLY" "$work/verify.err" ||
  fail "verify of a 3DGS export: $(cat "$work/verify.err")"

check_file() {  # FILE EXPECTED_COUNT
  local file=$1 count=$2
  local header_len
  header_len=$(grep -a -b -m1 '^end_header$' "$file" | cut -d: -f1) || fail "$file: no end_header"
  header_len=$((header_len + 11))
  head -c "$header_len" "$file" | grep -av '^comment ' >"$work/header"
  printf '%s\n' ply 'format binary_little_endian 1.0' "element vertex $count" \
    'property float x' 'property float y' 'property float z' 'property float nx' 'property float ny' 'property float nz' \
    'property float f_dc_0' 'property float f_dc_1' 'property float f_dc_2' 'property float opacity' \
    'property float scale_0' 'property float scale_1' 'property float scale_2' \
    'property float rot_0' 'property float rot_1' 'property float rot_2' 'property float rot_3' end_header >"$work/expected"
  diff "$work/expected" "$work/header" >/dev/null || fail "$file: header differs: $(diff "$work/expected" "$work/header")"
  local size
  size=$(stat -c %s "$file")
  [ "$size" -eq $((header_len + count * 17 * 4)) ] || fail "$file: $size bytes, expected $((header_len + count * 17 * 4))"
  od -A n -v -t f4 -w68 -j "$header_len" "$file" | awk -v count="$count" '
    function abs(x) { return x < 0 ? -x : x }
    NF != 17 { print "row " NR ": " NF " values"; bad = 1; exit }
    {
      nx = $4; ny = $5; nz = $6; op = $10; s0 = $11; s1 = $12; s2 = $13; w = $14; x = $15; y = $16; z = $17
      if (abs(w*w + x*x + y*y + z*z - 1) > 1e-5) { print "row " NR ": quaternion not unit"; bad = 1 }
      # R e_z = third column of the rotation matrix of (w, x, y, z)
      rx = 2*(x*z + w*y); ry = 2*(y*z - w*x); rz = 1 - 2*(x*x + y*y)
      if (abs(rx - nx) + abs(ry - ny) + abs(rz - nz) > 1e-4) { print "row " NR ": R z != normal"; bad = 1 }
      if (abs(nx*nx + ny*ny + nz*nz - 1) > 1e-5) { print "row " NR ": normal not unit"; bad = 1 }
      if (!(s2 < s1 && s1 <= s0 + 1e-6)) { print "row " NR ": scales " s0 " " s1 " " s2; bad = 1 }
      if (abs(1 / (1 + exp(-op)) - 0.99) > 1e-5) { print "row " NR ": opacity " op; bad = 1 }
      for (c = 7; c <= 9; ++c) { v = 0.5 + 0.28209479177387814 * $c; if (v < -1e-5 || v > 1 + 1e-5) { print "row " NR ": colour " v; bad = 1 } }
      rows++
    }
    END { if (!bad && rows != count) { print rows " rows, expected " count; bad = 1 } exit bad }' ||
    fail "$file: a Gaussian is wrong"
}

count=$(vertex_count "$cube_ply")
[ -n "$count" ] && [ "$count" -gt 0 ] || fail "$cube_ply: no vertex count"
check_file "$out" "$count"

# --clip: written unclipped, with one warning line giving the clipped count (the splat PLY has
# clip_offset properties, so this run does clip).
grep -aq '^property float clip_offset$' "$clip_ply" || fail "$clip_ply has no clip lines"
"$splatcl" splats "$cube" --samples grid:8 --eps 0.002 --color-field hard --color-tol 40 --clip --format 3dgs \
  -o "$work/clip-3dgs.ply" 2>"$work/stderr" >/dev/null || fail "--clip --format 3dgs failed: $(cat "$work/stderr")"
count=$(vertex_count "$clip_ply")
check_file "$work/clip-3dgs.ply" "$count"
grep -v '^splatcl: note: ' "$work/stderr" >"$work/warnings"
[ "$(grep -c . "$work/warnings")" -eq 1 ] || fail "expected one warning line, got: $(cat "$work/stderr")"
clipped=$(sed -nE "s/^splatcl: warning: ([0-9]+) of $count splats are clipped; 3DGS has no clip lines.*/\1/p" "$work/warnings")
[ -n "$clipped" ] && [ "$clipped" -ge 1 ] && [ "$clipped" -le "$count" ] ||
  fail "warning '$(cat "$work/warnings")' does not give a clipped count of the $count splats"
echo "ok: $count Gaussians; with --clip $clipped of $count clipped, written whole"
