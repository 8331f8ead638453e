#!/usr/bin/env bash
# Reproduces the size tables of docs/results/csm.md: one `splatcl csm build` per model × maps ×
# resolution, one at a time, each printed as a markdown row (segments, plain and compact MiB and
# ratios, the thesis's Tab. A.6 figure for the bunny at the default settings, wall time and peak
# RSS from /usr/bin/time).
# The .csm files go to a scratch directory and are deleted after each row.
#
#   scripts/csm-size-sweep.sh [--splatcl BIN] [--scratch DIR] [--maps "1024 4096"] [--res "64 128"]
#                             [--nice N] MODEL... [-- EXTRA BUILD ARGS]
#
# Defaults: BIN = build/splatcl, DIR = /tmp, maps "1024 4096 16384 65536", res "64 128 256", nice 19.
# Extra build arguments go last, after `--` (e.g. `-- --order hilbert`); they are passed to every
# build and shown in the first column.
# Sizes and segment counts do not depend on machine load; the two timing columns do.
set -euo pipefail

splatcl=build/splatcl
scratch=/tmp
maps_list="1024 4096 16384 65536"
res_list="64 128 256"
niceness=19
models=()
extra=()
while (($#)); do
  case "$1" in
    --splatcl) splatcl=$2; shift 2 ;;
    --scratch) scratch=$2; shift 2 ;;
    --maps) maps_list=$2; shift 2 ;;
    --res) res_list=$2; shift 2 ;;
    --nice) niceness=$2; shift 2 ;;
    -h|--help) sed -n '2,14p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    --) shift; extra=("$@"); break ;;
    -*) echo "csm-size-sweep: unknown option $1 (see --help)" >&2; exit 2 ;;
    *) models+=("$1"); shift ;;
  esac
done
((${#models[@]})) || { echo "csm-size-sweep: no MODEL given (see --help)" >&2; exit 2; }
[[ -x $splatcl ]] || { echo "csm-size-sweep: $splatcl is not an executable splatcl (use --splatcl)" >&2; exit 2; }
[[ -x /usr/bin/time ]] || { echo "csm-size-sweep: /usr/bin/time is required (apt-get install time)" >&2; exit 2; }

# Thesis Tab. A.6 / A.3 (Stanford bunny, uniform, horizontal zigzag): "MiB ratio".
thesis() {
  case "$1x$2" in
    1024x64) echo "1.99 16:1" ;; 4096x64) echo "5.26 24:1" ;; 16384x64) echo "14.8 35:1" ;;
    1024x128) echo "7.57 17:1" ;; 4096x128) echo "19.1 27:1" ;; 16384x128) echo "50.6 41:1" ;;
    65536x128) echo "142 57:1" ;;
    1024x256) echo "30.0 17:1" ;; 4096x256) echo "73.9 28:1" ;; 16384x256) echo "190 43:1" ;;
    *) echo "— —" ;;
  esac
}

thousands() { echo "$1" | sed -e ':a' -e 's/\B[0-9]\{3\}\>/,&/' -e 'ta'; }

echo "| model | maps | res | segments | plain MiB | ratio | compact MiB | compact ratio | thesis MiB | thesis ratio | wall s | peak RSS MiB |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
for model in "${models[@]}"; do
  name=$(basename "$model"); name=${name%.*}
  label=$name${extra[*]:+ ${extra[*]}}
  for maps in $maps_list; do
    for res in $res_list; do
      out="$scratch/csm-sweep-$$-$name-$maps-$res.csm"
      log="$scratch/csm-sweep-$$.log"
      timing="$scratch/csm-sweep-$$.time"
      if ! nice -n "$niceness" /usr/bin/time -f "%e %M" -o "$timing" \
          "$splatcl" csm build "$model" -o "$out" --maps "$maps" --res "$res" "${extra[@]}" >"$log" 2>&1; then
        echo "csm-size-sweep: build failed for $name $maps x $res:" >&2
        tail -n 3 "$log" >&2
        rm -f "$out"
        exit 1
      fi
      rm -f "$out"
      segments=$(awk '$1 == "segments" {print $2}' "$log")
      # "size       uncompressed U MiB; plain P MiB (R:1); compact C MiB (Q:1, ...% of plain)"
      read -r plain ratio compact cratio < <(sed -n 's/^size .*plain \([0-9.]*\) MiB (\([0-9.]*:1\)); compact \([0-9.]*\) MiB (\([0-9.]*:1\),.*/\1 \2 \3 \4/p' "$log")
      read -r wall rss_kib <"$timing"
      read -r tmib tratio < <(if [[ $name == stanford-bunny && ${#extra[@]} -eq 0 ]]; then thesis "$maps" "$res"; else echo "— —"; fi)
      printf '| %s | %s | %s² | %s | %s | %s | %s | %s | %s | %s | %s | %d |\n' "$label" "$maps" "$res" "$(thousands "$segments")" \
        "$plain" "$ratio" "$compact" "$cratio" "$tmib" "$tratio" "$wall" $((rss_kib / 1024))
    done
  done
done
rm -f "$scratch/csm-sweep-$$.log" "$scratch/csm-sweep-$$.time"
