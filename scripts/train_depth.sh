#!/usr/bin/env bash
# Trains the compact depth-completion network on rendered net-pen scenes and exports it as ONNX.
#   scripts/train_depth.sh [--smoke] [--out models/compact_depth.onnx] [--samples N] [--minutes M]
# Renders N training scenes (seed 1) and N/10 validation scenes (seed 2) with `pensight
# depth-data` into .cache/depth_data/{train,val}, reused while their sample count, seed and
# format version (2, sim/depth_training.h) match;
# trains for M minutes of wall-clock time (scripts/train_depth.py), checks that pensight's engine
# imports the result, and writes OUT (320x240, 4:3 cameras), OUT with _512x288 (16:9 cameras, the
# same weights) and OUT.json. An interrupted run resumes from
# .cache/depth_data/checkpoint.pt; a finished one removes it, so the next run starts over.
# --smoke: 8 + 4 scenes and 2 steps in a temporary folder, removed at exit (checks the toolchain).
# Defaults: 3000 samples, 100 minutes.
set -euo pipefail
cd "$(dirname "$0")/.."

usage() {
  echo "usage: $0 [--smoke] [--out FILE.onnx] [--samples N] [--minutes M]" >&2
  exit 2
}

smoke=0 out=models/compact_depth.onnx samples=3000 minutes=100
while [[ $# -gt 0 ]]; do
  case $1 in
    --smoke) smoke=1 ;;
    --out) [[ $# -ge 2 ]] || usage; out=$2; shift ;;
    --samples) [[ $# -ge 2 ]] || usage; samples=$2; shift ;;
    --minutes) [[ $# -ge 2 ]] || usage; minutes=$2; shift ;;
    *) usage ;;
  esac
  shift
done
if [[ ! $samples =~ ^[1-9][0-9]*$ || ! $minutes =~ ^[0-9]+(\.[0-9]+)?$ ]]; then
  echo "train_depth: --samples wants a positive integer and --minutes a number" >&2
  exit 2
fi

pensight=${PENSIGHT_BIN:-build/apps/pensight}  # the tests point it at their build's binary
if [[ ! -x $pensight ]]; then
  echo "train_depth: $pensight is missing; build it first with scripts/setup.sh" >&2
  exit 2
fi

# The value of `key:` in a depth-data folder's depth_data.txt (empty when absent).
meta() {
  awk -F': *' -v k="$2" '$1 == k { print $2 }' "$1/depth_data.txt" 2>/dev/null || true
}

if [[ $smoke -eq 1 ]]; then
  tmp=$(mktemp -d)
  trap 'rm -rf "$tmp"' EXIT
  "$pensight" depth-data --out "$tmp/train" --samples 8 --seed 1 --quiet
  "$pensight" depth-data --out "$tmp/val" --samples 4 --seed 2 --quiet
  /usr/bin/python3 scripts/train_depth.py --data "$tmp/train" --val "$tmp/val" \
    --out "$tmp/smoke.onnx" --max-steps 2 --also-export 512x288
  "$pensight" export-onnx "$tmp/smoke.onnx" --out "$tmp/roundtrip.onnx"
  "$pensight" export-onnx "$tmp/smoke_512x288.onnx" --out "$tmp/roundtrip.onnx"
  echo "train_depth: smoke test passed"
  exit 0
fi

data=.cache/depth_data
checkpoint=$data/checkpoint.pt
mkdir -p "$data" "$(dirname "$out")"
for spec in "train $samples 1" "val $((samples / 10 > 0 ? samples / 10 : 1)) 2"; do
  read -r name n seed <<<"$spec"
  if [[ $(meta "$data/$name" samples) == "$n" && $(meta "$data/$name" seed) == "$seed" &&
        $(meta "$data/$name" version) == 2 ]]; then
    echo "train_depth: reusing $data/$name ($n samples, seed $seed)"
  else
    "$pensight" depth-data --out "$data/$name" --samples "$n" --seed "$seed"
    rm -f "$checkpoint"  # a checkpoint belongs to the data it was trained on
  fi
done
/usr/bin/python3 scripts/train_depth.py --data "$data/train" --val "$data/val" --out "$out" \
  --minutes "$minutes" --epochs 1000 --threads "$(nproc)" --checkpoint "$checkpoint" \
  --also-export 512x288
roundtrip=$(mktemp --suffix=.onnx)
trap 'rm -f "$roundtrip"' EXIT
"$pensight" export-onnx "$out" --out "$roundtrip"
"$pensight" export-onnx "${out%.onnx}_512x288.onnx" --out "$roundtrip"
rm -f "$checkpoint"
echo "train_depth: wrote $out and $out.json"
