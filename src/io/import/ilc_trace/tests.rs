use super::*;

fn read(text: &str) -> Result<IlcTrace> {
    let dir = tempfile::tempdir().expect("tempdir");
    let p = dir.path().join("trace.txt");
    std::fs::write(&p, text).expect("write");
    read_ilc_trace(&p, &IlcImportConfig::default())
}

/// A small trace: 3 IMU epochs, one scan with a stale reading, two waypoints.
fn trace() -> String {
    let mut s =
        String::from("#\tstartTime:1000\n#\tSiteID:s1\tFloorName:F1\n#\tBrand:X\tModel:Y\n");
    s.push_str("1000\tTYPE_WAYPOINT\t1.5\t2.5\n");
    for (i, ms) in [1000, 1020, 1040].iter().enumerate() {
        let g = 0.1 * i as f64;
        s.push_str(&format!("{ms}\tTYPE_ACCELEROMETER\t0.1\t0.2\t9.8\t3\n"));
        s.push_str(&format!("{ms}\tTYPE_GYROSCOPE\t{g}\t0\t0\t3\n"));
        s.push_str(&format!(
            "{ms}\tTYPE_GYROSCOPE_UNCALIBRATED\t{g}\t0\t0\t0.01\t0\t0\t3\n"
        ));
        s.push_str(&format!("{ms}\tTYPE_MAGNETIC_FIELD\t20\t5\t-40\t3\n"));
        s.push_str(&format!("{ms}\tTYPE_ROTATION_VECTOR\t0\t0\t0.6\t3\n"));
    }
    s.push_str("1030\tTYPE_WIFI\tlab\tAA:BB:CC:DD:EE:01\t-50\t2412\t1000\n");
    s.push_str("1030\tTYPE_WIFI\tlab\taa:bb:cc:dd:ee:02\t-60\t5180\t-5000\n");
    s.push_str("1035\tTYPE_BEACON\tuuid\t0\t0\t-56\t-93\t1.0\tE0:78:A3:3D:B5:D6\t1035\n");
    s.push_str("1036\tTYPE_FANCY\t1\n");
    s.push_str("1040\tTYPE_WAYPOINT\t3.5\t4.5\n#\tendTime:1050\n");
    s
}

#[test]
fn converts_imu_wifi_and_waypoints_with_counts() {
    let r = read(&trace()).expect("valid");
    assert_eq!(r.imu.samples().len(), 3);
    let s0 = r.imu.samples()[0];
    assert_eq!(s0.t, 1.0);
    assert_eq!(s0.accel, [0.1, 0.2, 9.8]);
    let q = s0.orientation.expect("q");
    assert!((q[2] - 0.6).abs() < 1e-12 && (q[3] - 0.8).abs() < 1e-12);
    assert!((r.imu.samples()[2].gyro[0] - 0.2).abs() < 1e-12);
    assert_eq!(r.wifi.len(), 1);
    assert_eq!(r.wifi[0].t, 1.03);
    assert_eq!(r.wifi[0].readings[0].bssid, "aa:bb:cc:dd:ee:01");
    assert_eq!(r.waypoints.len(), 2);
    assert_eq!((r.waypoints[1].x, r.waypoints[1].y), (3.5, 4.5));
    let s = &r.summary;
    assert_eq!(s.stale_readings_dropped, 1);
    assert_eq!(s.imu_sources["gyroscope"], "TYPE_GYROSCOPE");
    assert_eq!(s.not_converted["TYPE_GYROSCOPE_UNCALIBRATED"], 3);
    assert_eq!(s.not_converted["TYPE_BEACON"], 1);
    assert_eq!(s.unknown_types["TYPE_FANCY"], 1);
    assert_eq!(s.floor_name.as_deref(), Some("F1"));
    assert_eq!(s.device.as_deref(), Some("X Y"));
    assert_eq!(s.header_lines, 4);
}

#[test]
fn uncalibrated_rows_stand_in_minus_their_bias() {
    let text: String = trace()
        .lines()
        .filter(|l| !l.contains("TYPE_GYROSCOPE\t"))
        .map(|l| format!("{l}\n"))
        .collect();
    let r = read(&text).expect("valid");
    assert_eq!(
        r.summary.imu_sources["gyroscope"],
        "TYPE_GYROSCOPE_UNCALIBRATED"
    );
    assert!((r.imu.samples()[0].gyro[0] + 0.01).abs() < 1e-12);
}

#[test]
fn errors_name_the_line() {
    let e = |text: &str| read(text).unwrap_err().to_string();
    let base = trace();
    let with = |line: &str| {
        base.replacen(
            "1000\tTYPE_WAYPOINT",
            &format!("{line}\n1000\tTYPE_WAYPOINT"),
            1,
        )
    };
    let m = e(&with("1000\tTYPE_ACCELEROMETER\t0.1\tNaN\t9.8\t3"));
    assert!(
        m.contains("trace.txt:4") && m.contains("acceleration y"),
        "{m}"
    );
    let m = e(&with("1000\tTYPE_GYROSCOPE\t0.1"));
    assert!(m.contains(":4") && m.contains("expected 3 or 4"), "{m}");
    let m = e(&with("10x0\tTYPE_GYROSCOPE\t0.1\t0\t0"));
    assert!(m.contains(":4") && m.contains("milliseconds"), "{m}");
    let m = e(&with("1000\tWIFI\t0.1"));
    assert!(m.contains(":4") && m.contains("row type"), "{m}");
    let m = e(&base.replace("1040\tTYPE_GYROSCOPE\t0.2", "900\tTYPE_GYROSCOPE\t0.2"));
    assert!(m.contains("before the same sensor's row at line"), "{m}");
    let no_gyro: String = base
        .lines()
        .filter(|l| !l.contains("TYPE_GYROSCOPE"))
        .map(|l| format!("{l}\n"))
        .collect();
    let m = e(&no_gyro);
    assert!(
        m.contains("trace.txt: ") && m.contains("no gyroscope rows"),
        "{m}"
    );
    let m = e("");
    assert!(m.contains("no data rows"), "{m}");
    let m = e(&with(
        "1000\tTYPE_WIFI\tlab\tAA:BB:CC:DD:EE:01\t-500\t2412\t1000",
    ));
    assert!(m.contains(":4") && m.contains("rssi"), "{m}");
}

#[test]
fn an_unterminated_malformed_last_line_is_skipped_and_reported() {
    let mut text = trace();
    text.push_str("1050\tTYPE_ACCELEROMETER\t0.1\t0.");
    let r = read(&text).expect("skipped");
    assert_eq!(r.summary.truncated_last_line, Some(text.lines().count()));
    // The same line terminated is an error.
    text.push_str("\t\n1060\tTYPE_GYROSCOPE\t0\t0\t0\n");
    assert!(read(&text).is_err());
    // A line cut mid-number parses, and is skipped all the same: it cannot be trusted.
    let mut cut = trace();
    let whole = read(&cut).expect("whole");
    cut.push_str("1050\tTYPE_ACCELEROMETER\t0.1\t0.2\t9.8");
    let r = read(&cut).expect("cut");
    assert_eq!(r.summary.truncated_last_line, Some(cut.lines().count()));
    assert_eq!(r.imu.samples().len(), whole.imu.samples().len());
    // A byte-order mark before the header is dropped.
    let r = read(&format!("\u{feff}{}", trace())).expect("bom");
    assert_eq!(r.imu.samples().len(), whole.imu.samples().len());
}
