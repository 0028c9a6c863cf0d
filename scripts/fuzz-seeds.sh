#!/usr/bin/env bash
# Writes the seed corpora of the fuzz targets (fuzz/corpus/<target>/) from the project's own
# files: the shipped scenarios, a small rendered sequence of follow.yaml and tank.yaml (160x120,
# 0.3 s) with `pensight run` and `pensight map --from-truth` outputs on it, and the engine's all-ops ONNX
# model. Needs the Release build (scripts/setup.sh). The committed seeds were written by it;
# rerun after a file format changes, then `scripts/fuzz.sh --merge TARGET` keeps what fuzzing
# found on top.
set -euo pipefail
cd "$(dirname "$0")/.."
cli="${PENSIGHT_BUILD_DIR:-build}/apps/pensight"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
out=fuzz/corpus
rm -rf "$out"
for t in $(scripts/fuzz.sh --list); do mkdir -p "$out/$t"; done

# head FILE: the header and first rows of a log (short seeds mutate faster).
head_of() { head -n 12 "$1"; }
# seed TARGET NAME SELECTOR FILE: FILE prefixed with the target's selector byte (octal).
seed() { { printf "\\$3"; head_of "$4"; } >"$out/$1/$2"; }

for s in follow tank; do
  sed 's/^camera: {samples_per_axis: 1}$/camera: {samples_per_axis: 1, resolution: [160, 120]}/' \
    "scenarios/$s.yaml" >"$tmp/$s.yaml"
  grep -q "resolution: \[160, 120\]" "$tmp/$s.yaml"
  "$cli" render "$tmp/$s.yaml" --out "$tmp/$s" --duration 0.3 --renderer cpu --quiet
  printf 'voxel_m: 0.05\nmax_range_m: 3\nthreads: 1\n' >"$tmp/map.yaml"
  "$cli" run "$tmp/$s" --out "$tmp/$s.out" --backend cpu --quiet --roi-rows 2 \
    --roi-cols 2 --roi-size 64 --fft-size 64
  "$cli" map "$tmp/$s" --out "$tmp/$s.out" --from-truth --config "$tmp/map.yaml" --quiet
  d="$tmp/$s"
  cp "$d/scene.yaml" "$out/scene_yaml/$s.yaml"
  cp "$d/cam0/sensor.yaml" "$out/camera_yaml/$s.yaml"
  cp "$d/dvl0/sensor.yaml" "$out/dvl_yaml/$s.yaml"
  seed dataset_csv "$s-cam0" 000 "$d/cam0/data.csv"
  seed dataset_csv "$s-dvl0" 001 "$d/dvl0/data.csv"
  seed dataset_csv "$s-pressure0" 002 "$d/pressure0/data.csv"
  seed dataset_csv "$s-imu0" 003 "$d/imu0/attitude.csv"
  seed dataset_csv "$s-groundtruth0" 004 "$d/groundtruth0/data.csv"
  seed result_csv "$s-estimates" 000 "$d.out/estimates.csv"
  seed result_csv "$s-global-pose" 001 "$d.out/global_pose_published.csv"
  seed result_csv "$s-tum" 002 "$d.out/trajectory_tum.txt"
  frame=$(ls "$d/cam0/data" | head -n 1)
  { printf '\000'; cat "$d/cam0/data/$frame"; } >"$out/png/$s-frame-any-size"
  { printf '\002'; cat "$d/cam0/data/$frame"; } >"$out/png/$s-frame-160x120"
  { printf '\003'; cat "$d/groundtruth0/depth/$frame"; } >"$out/png/$s-depth-160x120"
  cp "$d.out/map.vdb" "$out/map_vdb/$s.vdb"
done
# 0.3 s is too short for a pose in trajectory_tum.txt: two rows in its format.
printf '\002# timestamp tx ty tz qx qy qz qw\n1.0 11.2 0.1 3.0 0 0 0.0499792 0.9987503\n1.1 11.2 0.13 3.0 0 0 0.0499792 0.9987503\n' \
  >"$out/result_csv/tum-two-poses"
cp "$tmp/map.yaml" "$out/map_config/coarse.yaml"
printf '' >"$out/map_config/empty.yaml"
# The other form of beam_directions (dataset-format.md 1.1): a list of 3-vectors.
sed '/^beam_directions:/,$d' "$out/dvl_yaml/follow.yaml" >"$out/dvl_yaml/beam-list.yaml"
printf 'beam_directions: [[0.5, 0.5, 0.7071], [0.5, -0.5, 0.7071], [-0.5, -0.5, 0.7071], [-0.5, 0.5, 0.7071]]\n' \
  >>"$out/dvl_yaml/beam-list.yaml"
cp scenarios/*.yaml "$out/scenario_yaml/"
"$cli" export-onnx builtin:all-ops --out "$out/onnx/all_ops.onnx" >/dev/null
# MAVLink: the datagrams `pensight closed-loop --mavlink` sends in its first 0.2 s (HEARTBEAT,
# COMMAND_LONG arm, SET_MODE, MANUAL_CONTROL), caught by a small UDP listener.
port=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
python3 - "$port" "$out/mavlink" <<'PY' &
import socket, sys
s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
s.bind(("127.0.0.1", int(sys.argv[1])))
s.settimeout(30)
for i in range(8):
    data, _ = s.recvfrom(65536)
    open(f"{sys.argv[2]}/closed-loop-{i}", "wb").write(data)
PY
listener=$!
sleep 0.5
"$cli" closed-loop scenarios/hold_0p5.yaml --out "$tmp/closed_loop" --duration 0.5 --quiet \
  --mavlink "udpout:127.0.0.1:$port" >/dev/null
wait "$listener"
# ... and what an ArduSub vehicle sends back (HEARTBEAT armed in ALT_HOLD, ATTITUDE,
# SCALED_PRESSURE), encoded by node-mavlink (scripts/test.sh installs it), one file whole and the
# same behind garbage bytes.
cat >"$tmp/vehicle.txt" <<'TXT'
0 0 1 1 type=12 autopilot=3 base_mode=209 custom_mode=2 system_status=4 mavlink_version=3
30 1 1 1 time_boot_ms=1000 roll=0.01 pitch=-0.02 yaw=1.5 rollspeed=0 pitchspeed=0 yawspeed=0.1
29 2 1 1 time_boot_ms=1000 press_abs=1313.25 press_diff=0 temperature=1500
TXT
NODE_PATH=.cache/node-mavlink/node_modules node tests/mavlink/node_mavlink.js encode \
  "$tmp/vehicle.txt" "$out/mavlink/vehicle-stream"
{ printf '\xfe\x09garbage\xfd\x01'; cat "$out/mavlink/vehicle-stream"; } >"$out/mavlink/vehicle-after-garbage"
du -sh "$out"
