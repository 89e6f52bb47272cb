use super::*;

fn read(text: &str) -> Result<IpinLog> {
    let dir = tempfile::tempdir().expect("tempdir");
    let p = dir.path().join("log.txt");
    std::fs::write(&p, text).expect("write");
    read_ipin_log(&p, &IpinImportConfig::default())
}

#[test]
fn converts_every_stream_of_a_synthetic_log() {
    let log = read(&synthetic_ipin_log(4, 40.3, -3.7)).expect("valid");
    assert_eq!(log.imu.samples().len(), 200);
    assert!((log.imu.report().rate_hz - 50.0).abs() < 0.5);
    assert!(log.imu.has_magnetometer() && log.imu.has_orientation() && log.imu.has_pressure());
    assert_eq!(log.wifi.len(), 4);
    assert_eq!(log.wifi[0].readings.len(), 2);
    assert_eq!(log.summary.stale_readings_dropped, 4);
    assert_eq!(log.wifi[0].readings[1].freq, Some(5180.0));
    assert_eq!(log.gnss.len(), 4);
    assert_eq!(log.gnss[0].accuracy, 12.0);
    assert_eq!(log.positions.len(), 2);
    assert_eq!(log.summary.skipped_tags["LIGH"], 40);
    assert_eq!(log.summary.skipped_tags["SOUN"], 4);
    let frame = LocalFrame::new(40.3, -3.7).expect("frame");
    let w = positions_to_waypoints(&log.positions, &frame);
    assert!(
        w[0].x.abs() < 0.01 && (w[1].x - 2.0).abs() < 0.02 && w[1].y.abs() < 0.01,
        "{w:?}"
    );
    assert_eq!(w[1].level, Some(0));
    // The AHRS rotation vector (0.01, -0.005, 0.7071) gives w ≈ 0.7070.
    let q = log.imu.samples()[10].orientation.expect("q");
    assert!((q[3] - 0.70703).abs() < 1e-4, "{q:?}");
}

#[test]
fn old_wifi_lines_and_ssids_with_semicolons_are_read() {
    let mut text = synthetic_ipin_log(1, 40.3, -3.7);
    text.push_str("WIFI;1.500;9.0;a;b;00:11:22:33:44:58;-70\n");
    text.push_str("WIFI;1.500;9.0;net;00:11:22:33:44:59;-71\n");
    let log = read(&text).expect("valid");
    let last = log.wifi.last().expect("scan");
    assert_eq!(last.readings[0].ssid.as_deref(), Some("a;b"));
    assert_eq!(last.readings[1].freq, None);
}

#[test]
fn errors_name_the_line() {
    let base = synthetic_ipin_log(1, 40.3, -3.7);
    let e = |extra: &str| read(&format!("{base}{extra}\n")).unwrap_err().to_string();
    let n = base.lines().count() + 1;
    let m = e("ACCE;1.0;1.0;0.1;NaN;9.8;3");
    assert!(
        m.contains(&format!("log.txt:{n}")) && m.contains("acceleration y"),
        "{m}"
    );
    let m = e("GYRO;1.0;1.0;0.1");
    assert!(
        m.contains(&format!(":{n}")) && m.contains("expected 6 or 7"),
        "{m}"
    );
    let m = e("ACCE;0.1;1.0;0.1;0.1;9.8;3");
    assert!(
        m.contains(&format!(":{n}")) && m.contains("before the same sensor's"),
        "{m}"
    );
    let m = e("hello world");
    assert!(m.contains(&format!(":{n}")) && m.contains("TAG"), "{m}");
    let m = e("POSI;2.0;3;40.3;-3.7;0.5;1");
    assert!(m.contains("floor ID"), "{m}");
    let no_gyro: String = base
        .lines()
        .filter(|l| !l.starts_with("GYRO"))
        .map(|l| format!("{l}\n"))
        .collect();
    let m = read(&no_gyro).unwrap_err().to_string();
    assert!(m.contains("log.txt: ") && m.contains("no gyroscope"), "{m}");
    let m = read("% only comments\n").unwrap_err().to_string();
    assert!(m.contains("no data lines"), "{m}");
    // Unknown tags are skipped, not errors.
    let log = read(&format!("{base}ZZZZ;1;2;3\n")).expect("valid");
    assert_eq!(log.summary.skipped_tags["ZZZZ"], 1);
}
