#!/usr/bin/env bash
# Regenerates the fuzz seed corpora (fuzz/corpus/NAME/) from the bundled data and the
# toolkit's own outputs: a few small valid files per reader, which the fuzzer mutates and
# tests/it/fuzz_replay.rs replays on the stable toolchain. Run from the repository root after
# `cargo build --release`.
set -euo pipefail
bin=target/release/footslam
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
c=fuzz/corpus
rm -rf "$c"
mkdir -p $c/{steps_csv,imu_csv,wifi_csv,gps_csv,gpx,eval_csv,floor_plan,outline,radio_map,hex_map,manifest,config,ilc_trace,ilc_floor,ipin_log}

"$bin" simulate --building campus --seed 1 --out "$work/campus" > /dev/null
"$bin" learn --particles 50 --out "$work/learn" > /dev/null
"$bin" survey --steps datasets/tower/steps.csv --wifi datasets/tower/wifi.csv \
    --plan datasets/tower/floor.geojson --out "$work/survey" > /dev/null
"$bin" track --steps datasets/office/steps.csv --plan datasets/office/floor.geojson \
    --start 0,0 --out "$work/track" > /dev/null 2>&1 || true
"$bin" steps --imu tests/data/phone_excerpt.csv --mount phone --out "$work/steps" > /dev/null

head -40 datasets/office/steps.csv > $c/steps_csv/office.csv
head -40 datasets/tower/steps.csv > $c/steps_csv/tower.csv
head -40 "$work/steps/steps.csv" > $c/steps_csv/with_heading.csv
head -300 tests/data/foot_excerpt.csv > $c/imu_csv/foot.csv
head -150 tests/data/phone_excerpt.csv > $c/imu_csv/phone.csv
head -30 datasets/tower/wifi.csv > $c/wifi_csv/tower.csv
head -20 "$work/campus/gps.csv" > $c/gps_csv/campus.csv
cat > $c/gpx/two_fixes.gpx <<'GPX'
<?xml version="1.0" encoding="UTF-8"?>
<gpx version="1.1" creator="footslam"><trk><trkseg>
<trkpt lat="52.0001" lon="0.1002"><ele>12.5</ele><time>2024-05-01T10:00:00Z</time><hdop>1.5</hdop></trkpt>
<trkpt lat="52.0002" lon="0.1003"><time>2024-05-01T10:00:01.5Z</time></trkpt>
</trkseg></trk></gpx>
GPX
head -30 datasets/office/truth.csv > $c/eval_csv/truth.csv
head -30 "$work/track/track.csv" > $c/eval_csv/track.csv 2>/dev/null || true
printf 't,x,y\n1700000000.5,1.0,2.0\n1700000010.0,5.5,-3.25\n' > $c/eval_csv/waypoints.csv
cp datasets/office/floor.geojson $c/floor_plan/office.geojson
cp "$work/campus/outline.geojson" $c/outline/campus.geojson
python3 - "$work" "$c" <<'PY'
import json, sys
work, c = sys.argv[1], sys.argv[2]
def trim(src, dst, n):
    d = json.load(open(src))
    d["features"] = d["features"][:n]
    json.dump(d, open(dst, "w"), separators=(",", ":"))
trim(f"{work}/survey/radiomap.geojson", f"{c}/radio_map/tower.geojson", 3)
trim(f"{work}/learn/map.geojson", f"{c}/hex_map/office.geojson", 6)
trim("datasets/tower/floor.geojson", f"{c}/floor_plan/tower_two_surfaces.geojson", 2)
PY
printf 'steps,gps,wifi,start\na/steps.csv,a/gps.csv,,"1.5,-2,0.3,1"\nb/steps.csv,,b/wifi.csv,\n' > $c/manifest/walks.csv
cp "$work/learn/config.json" $c/config/footslam.json
cp "$work/track/config.json" $c/config/tracker.json 2>/dev/null || true
cp "$work/steps/config.json" $c/config/steps.json
cp datasets/office/config.json $c/config/sim.json
printf 'particles = 2000\nseed = 3\n[motion]\nlength_sigma = 0.1\n' > $c/config/footslam.toml
head -60 tests/data/ilc_excerpt.txt > $c/ilc_trace/excerpt.txt
python3 - "$c" <<'PY'
import sys
c = sys.argv[1]
lon = lambda x: 120.0 + x / 200.0 * 0.002
lat = lambda y: 30.0 + y / 150.0 * 0.0015
def rect(x0, y0, x1, y1):
    pts = [(x0, y0), (x1, y0), (x1, y1), (x0, y1), (x0, y0)]
    return [[[lon(x), lat(y)] for x, y in pts]]
import json
info = json.dumps({"map_info": {"width": 200.0, "height": 150.0}})
fmap = json.dumps({"type": "FeatureCollection", "features": [
    {"type": "Feature", "properties": {"name": "F1"}, "geometry": {"type": "MultiPolygon", "coordinates": [rect(0, 0, 200, 150)]}},
    {"type": "Feature", "properties": {"name": "shop"}, "geometry": {"type": "Polygon", "coordinates": rect(10, 10, 40, 40)}}]})
open(f"{c}/ilc_floor/floor.bin", "wb").write(info.encode() + b"\0" + fmap.encode())
PY
cat > $c/ipin_log/short.txt <<'LOG'
% LogFile created by the 'GetSensorData' App for Android.
ACCE;0.000;1000.000;0.00000;0.20000;9.81000;3
GYRO;0.004;1000.000;0.05000;-0.02000;0.01000;3
MAGN;0.006;1000.000;21.5;4.2;-38.9;3
AHRS;0.008;1000.000;1.2;-0.8;90.0;0.01;-0.005;0.70710678;3
PRES;0.009;1000.000;1013.25;3
ACCE;0.020;1000.020;0.10000;0.20000;10.2;3
GYRO;0.024;1000.020;0.04000;-0.02000;0.01000;3
WIFI;0.031;5000.031;lab;00:11:22:33:44:55;2412;-55
GNSS;0.031;1600000000.031;40.31300000;-3.48300000;410.0;90.0;12.0;1.0;1600000000031;9;7
POSI;0.040;1;40.31300000;-3.48300000;0;1
ACCE;0.040;1000.040;0.20000;0.20000;11.0;3
LOG
du -sh $c; find $c -type f | wc -l
