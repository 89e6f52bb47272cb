#!/usr/bin/env python3
"""Convert a WiFi scan log into footslam's `wifi.csv` (`t,bssid,rssi,ssid,freq`).

Phone loggers and public indoor-positioning datasets write one line per access point
sighting, with the columns in their own order, often next to other sensors' lines in the
same file. footslam wants one row per sighting, the rows of one scan sharing `t`, on the
step trace's clock. This script picks the columns by position, keeps the lines of one tag,
groups sightings into scans and shifts the clock:

    # IPIN-competition-style logfile lines `WIFI;AppTimestamp;SensorTimestamp;SSID;BSSID;
    # Frequency;RSS` (check your logfile version's header for the column order):
    scripts/wifi_log_to_csv.py log.txt --tag WIFI --sep ';' --t 1 --ssid 3 --bssid 4 \
        --freq 5 --rssi 6 > wifi.csv

    # A CSV from an Android logger with a header (columns counted from 0, header skipped):
    scripts/wifi_log_to_csv.py scans.csv --skip 1 --t 0 --bssid 1 --rssi 2 --t-scale 1e-3

Scans: sightings whose time is within `--gap` seconds (default 0.5), before or after, of
the first sighting of the current scan belong to it and get its time (a scan's results arrive together; an
AP's own "last seen" time would split one scan apart, so pick the time the app received the
results). A BSSID seen twice in one scan keeps its strongest reading. `--t0` is subtracted
from every time after `--t-scale` (e.g. the Unix time of the step trace's t = 0).

Lines that are malformed (too few fields, a time or RSSI that is not a number, an RSSI
outside -120..0 dBm, an empty BSSID) stop the conversion with the file and line named, as
footslam itself does; times must not go back by more than `--gap`.
"""
import argparse
import csv
import math
import sys


def parse_args(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("log", help="the log file")
    p.add_argument("--sep", default=",", help="field separator (default ',')")
    p.add_argument("--tag", help="keep only lines whose first field is this (e.g. WIFI)")
    p.add_argument("--skip", type=int, default=0, help="header lines to skip")
    p.add_argument("--t", type=int, required=True, help="column of the time")
    p.add_argument("--bssid", type=int, required=True, help="column of the BSSID")
    p.add_argument("--rssi", type=int, required=True, help="column of the RSSI, dBm")
    p.add_argument("--ssid", type=int, help="column of the SSID")
    p.add_argument("--freq", type=int, help="column of the frequency, MHz")
    p.add_argument("--t-scale", type=float, default=1.0, help="seconds per time unit")
    p.add_argument("--t0", type=float, default=0.0, help="subtracted from every time, s")
    p.add_argument("--gap", type=float, default=0.5, help="longest spread of one scan, s")
    return p.parse_args(argv)


def number(text, what, where):
    try:
        v = float(text)
    except ValueError:
        sys.exit(f"{where}: {what} `{text}` is not a number")
    if not math.isfinite(v):
        sys.exit(f"{where}: {what} `{text}` is not finite")
    return v


def main(argv):
    a = parse_args(argv)
    needed = max(c for c in (a.t, a.bssid, a.rssi, a.ssid, a.freq) if c is not None)
    scans = []  # [t, {bssid: (rssi, ssid, freq)}]
    with open(a.log, newline="", encoding="utf-8-sig") as f:
        for line_no, fields in enumerate(csv.reader(f, delimiter=a.sep), start=1):
            if line_no <= a.skip or not fields or not "".join(fields).strip():
                continue
            if a.tag is not None and fields[0].strip() != a.tag:
                continue
            where = f"{a.log}:{line_no}"
            if len(fields) <= needed:
                sys.exit(f"{where}: {len(fields)} fields, column {needed} asked for")
            t = number(fields[a.t], "time", where) * a.t_scale - a.t0
            rssi = number(fields[a.rssi], "RSSI", where)
            if not -120.0 <= rssi <= 0.0:
                sys.exit(f"{where}: RSSI {rssi} dBm is outside -120..0")
            bssid = fields[a.bssid].strip().lower()
            if not bssid:
                sys.exit(f"{where}: empty BSSID")
            ssid = fields[a.ssid].strip() if a.ssid is not None else ""
            freq = fields[a.freq].strip() if a.freq is not None else ""
            if scans and t < scans[-1][0] - a.gap:
                sys.exit(f"{where}: time {t} is before the previous scan's {scans[-1][0]}")
            if not scans or t - scans[-1][0] > a.gap:
                scans.append([t, {}])
            seen = scans[-1][1]
            if bssid not in seen or seen[bssid][0] < rssi:
                seen[bssid] = (rssi, ssid, freq)
    if not scans:
        sys.exit(f"{a.log}: no WiFi sightings")
    out = csv.writer(sys.stdout, lineterminator="\n")
    out.writerow(["t", "bssid", "rssi", "ssid", "freq"])
    for t, seen in scans:
        for bssid, (rssi, ssid, freq) in sorted(seen.items()):
            out.writerow([f"{t:.3f}", bssid, f"{rssi:g}", ssid, freq])


if __name__ == "__main__":
    main(sys.argv[1:])
