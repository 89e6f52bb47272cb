//! Inputs that are each well-formed but wrong together: every case must fail (or warn) with
//! a message naming the files and the way out, and write nothing — never a confident answer
//! with exit 0. One table, run end to end through the CLI on the bundled tower walk.

use crate::cli_cases::{Case, bundled, footslam, rewrite, run_case, with_field};
use std::path::Path;

#[test]
fn inputs_wrong_together_fail_or_warn_clearly() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    let (plan, steps, wifi) = (
        bundled("floor.geojson"),
        bundled("steps.csv"),
        bundled("wifi.csv"),
    );
    // A radio map of the walk's own building.
    footslam()
        .args(["survey", "--plan"])
        .arg(&plan)
        .arg("--steps")
        .arg(&steps)
        .arg("--wifi")
        .arg(&wifi)
        .arg("--out")
        .arg(d.join("survey"))
        .assert()
        .success();
    // The same walk's log with every BSSID renamed: another building's access points.
    rewrite(&wifi, &d.join("renamed.csv"), |l| {
        with_field(l, 1, |b| b.replace("02:00", "0a:ff"))
    });
    // A quarter of the scans renamed: mostly another building.
    rewrite(&wifi, &d.join("mostly_renamed.csv"), |l| {
        let t: f64 = l.split(',').next().and_then(|t| t.parse().ok()).expect("t");
        if (t as u64).is_multiple_of(4) {
            l.to_owned()
        } else {
            with_field(l, 1, |b| b.replace("02:00", "0a:ff"))
        }
    });
    // The log on another clock.
    rewrite(&wifi, &d.join("late.csv"), |l| {
        with_field(l, 0, |t| format!("{}", t.parse::<f64>().expect("t") + 1e5))
    });
    // The log 300 s late: it still overlaps the walk (718 s), but 40 % of it lies after.
    rewrite(&wifi, &d.join("wifi_late.csv"), |l| {
        with_field(l, 0, |t| {
            format!("{}", t.parse::<f64>().expect("t") + 300.0)
        })
    });
    // The log in milliseconds.
    rewrite(&wifi, &d.join("ms.csv"), |l| {
        with_field(l, 0, |t| {
            format!("{}", t.parse::<f64>().expect("t") * 1e3 + 1.7e12)
        })
    });
    // A radio map with an absurd threshold.
    let mut wild: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(d.join("survey/radiomap.geojson")).expect("map"),
    )
    .expect("json");
    wild["epsilon_sqrt"] = 1e308.into();
    std::fs::write(d.join("wild_epsilon.geojson"), wild.to_string()).expect("wild");
    // The steps without their height changes.
    rewrite(&steps, &d.join("flat.csv"), |l| {
        let f: Vec<&str> = l.split(',').collect();
        f[..3].join(",")
    });
    let text = std::fs::read_to_string(d.join("flat.csv")).expect("flat");
    std::fs::write(
        d.join("flat.csv"),
        text.replacen("t,length,dheading,dz", "t,length,dheading", 1),
    )
    .expect("header");

    let p = |p: &Path| p.display().to_string();
    let s = |x: &str| x.to_owned();
    let radiomap = p(&d.join("survey/radiomap.geojson"));
    let track = |steps: &str, wifi: &str| {
        vec![
            s("track"),
            s("--plan"),
            p(&plan),
            s("--steps"),
            s(steps),
            s("--radiomap"),
            radiomap.clone(),
            s("--wifi"),
            s(wifi),
        ]
    };
    let survey = |steps: &str, wifi: &str| {
        vec![
            s("survey"),
            s("--plan"),
            p(&plan),
            s("--steps"),
            s(steps),
            s("--wifi"),
            s(wifi),
        ]
    };
    let (steps_s, flat) = (p(&steps), p(&d.join("flat.csv")));
    let cases = [
        Case {
            name: "radio map and WiFi log share no access point",
            args: track(&steps_s, &p(&d.join("renamed.csv"))),
            fails: true,
            says: &["renamed.csv", "radiomap.geojson", "none of the log's"],
        },
        Case {
            name: "most scans hear no access point of the map",
            args: track(&steps_s, &p(&d.join("mostly_renamed.csv"))),
            fails: false,
            says: &["warning", "mostly_renamed.csv", "hear an access point"],
        },
        Case {
            name: "a region threshold of 0",
            args: {
                let mut a = track(&steps_s, &p(&wifi));
                a.extend([s("--rf-epsilon"), s("0")]);
                a
            },
            fails: true,
            says: &["rf.epsilon", "0"],
        },
        Case {
            name: "WiFi times in milliseconds",
            args: track(&steps_s, &p(&d.join("ms.csv"))),
            fails: true,
            says: &["ms.csv", "beyond 1e11 s", "milliseconds"],
        },
        Case {
            name: "a radio map whose threshold is absurd",
            args: {
                let mut a = track(&steps_s, &p(&wifi));
                a[6] = p(&d.join("wild_epsilon.geojson"));
                a
            },
            fails: true,
            says: &["wild_epsilon.geojson", "epsilon_sqrt"],
        },
        Case {
            name: "track: WiFi log on another clock",
            args: track(&steps_s, &p(&d.join("late.csv"))),
            fails: true,
            says: &["late.csv", "no scan falls within the walk's time span"],
        },
        Case {
            name: "track: WiFi log 300 s late (overlapping the walk)",
            args: track(&steps_s, &p(&d.join("wifi_late.csv"))),
            fails: false,
            says: &[
                "wifi_late.csv",
                "lie more than 10 s outside the walk's time span",
            ],
        },
        Case {
            name: "survey: WiFi log on another clock",
            args: survey(&steps_s, &p(&d.join("late.csv"))),
            fails: true,
            says: &["late.csv", "one clock"],
        },
        Case {
            name: "fingerprint: radio map of another building",
            args: vec![
                s("fingerprint"),
                s("--radiomap"),
                radiomap.clone(),
                s("--wifi"),
                p(&d.join("renamed.csv")),
            ],
            fails: true,
            says: &["renamed.csv", "access point"],
        },
        Case {
            name: "track: steps without dz on a plan of three floors",
            args: vec![
                s("track"),
                s("--plan"),
                p(&plan),
                s("--steps"),
                flat.clone(),
            ],
            fails: true,
            says: &["flat.csv", "dz", "3 levels", "--one-floor"],
        },
        Case {
            name: "survey: steps without dz on a plan of three floors",
            args: survey(&flat, &p(&wifi)),
            fails: true,
            says: &["flat.csv", "dz", "--one-floor"],
        },
        Case {
            name: "track: steps without dz, the walk said to stay on one floor",
            args: vec![
                s("track"),
                s("--plan"),
                p(&plan),
                s("--steps"),
                flat,
                s("--one-floor"),
            ],
            fails: false,
            says: &[],
        },
    ];
    for (i, case) in cases.iter().enumerate() {
        let out = d.join(format!("out-{i}"));
        run_case(case, &out);
        assert_eq!(out.exists(), !case.fails, "{}: outputs", case.name);
    }
}

/// The bundled tower plan with `edit` applied to its GeoJSON.
fn edited_plan(to: &Path, edit: impl Fn(&mut serde_json::Value)) {
    let text = std::fs::read_to_string(bundled("floor.geojson")).expect("plan");
    let mut plan: serde_json::Value = serde_json::from_str(&text).expect("json");
    edit(&mut plan);
    std::fs::write(to, serde_json::to_string(&plan).expect("json")).expect("write");
}

/// Scales every position of a plan about its origin.
fn scale_plan(plan: &mut serde_json::Value, factor: f64) {
    let (lat0, lon0) = (
        plan["origin"]["lat"].as_f64().expect("lat"),
        plan["origin"]["lon"].as_f64().expect("lon"),
    );
    fn walk(v: &mut serde_json::Value, f: &dyn Fn(&mut serde_json::Value)) {
        match v {
            serde_json::Value::Array(a) if a.len() == 2 && a.iter().all(|x| x.is_f64()) => f(v),
            serde_json::Value::Array(a) => a.iter_mut().for_each(|x| walk(x, f)),
            _ => {}
        }
    }
    for feature in plan["features"].as_array_mut().expect("features") {
        walk(&mut feature["geometry"]["coordinates"], &|p| {
            let (lon, lat) = (p[0].as_f64().expect("lon"), p[1].as_f64().expect("lat"));
            *p = serde_json::json!([lon0 + (lon - lon0) * factor, lat0 + (lat - lat0) * factor]);
        });
    }
}

#[test]
fn files_out_of_range_or_ambiguous_fail_clearly() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    let steps = bundled("steps.csv");
    edited_plan(&d.join("high.geojson"), |p| {
        p["features"][0]["properties"]["z"] = 1e308.into()
    });
    edited_plan(&d.join("tiny.geojson"), |p| scale_plan(p, 1e-4));
    edited_plan(&d.join("huge.geojson"), |p| scale_plan(p, 400.0));
    edited_plan(&d.join("far.geojson"), |p| {
        let lat = p["origin"]["lat"].as_f64().expect("lat");
        p["origin"]["lat"] = (lat + 1.0).into();
    });
    // A round hall drawn with 20,001 vertices (validating it compares every pair of edges).
    edited_plan(&d.join("dense.geojson"), |p| {
        let first = p["features"][0]["geometry"]["coordinates"][0][0].clone();
        let (lon, lat) = (
            first[0].as_f64().expect("lon"),
            first[1].as_f64().expect("lat"),
        );
        let ring: Vec<serde_json::Value> = (0..=20_000)
            .map(|k| {
                let a = std::f64::consts::TAU * f64::from(k % 20_000) / 20_000.0;
                serde_json::json!([lon + 2e-4 * a.cos(), lat + 1.5e-4 * a.sin()])
            })
            .collect();
        p["features"][0]["geometry"] =
            serde_json::json!({"type": "Polygon", "coordinates": [ring]});
    });
    edited_plan(&d.join("twice.geojson"), |p| {
        let first = p["features"][0].clone();
        p["features"].as_array_mut().expect("features").push(first);
    });
    // A plan saved by an editor with a byte-order mark reads as any other.
    let text = std::fs::read_to_string(bundled("floor.geojson")).expect("plan");
    std::fs::write(d.join("bom.geojson"), format!("\u{feff}{text}")).expect("bom");
    let steps_text = std::fs::read_to_string(&steps).expect("steps");
    std::fs::write(
        d.join("two_t.csv"),
        steps_text.replacen("t,length,dheading,dz", "t,length,dheading,t", 1),
    )
    .expect("dup");
    // A `dz` column whose every cell is empty says nothing about height.
    let empty_dz: String = steps_text
        .lines()
        .enumerate()
        .map(|(i, l)| match i {
            0 => format!("{l}\n"),
            _ => {
                let mut f: Vec<&str> = l.split(',').collect();
                f[3] = "";
                format!("{}\n", f.join(","))
            }
        })
        .collect();
    std::fs::write(d.join("empty_dz.csv"), empty_dz).expect("empty dz");
    std::fs::write(d.join("cap.toml"), "[kld]\nmax_particles = 20000\n").expect("cap");
    // A learned map to merge.
    footslam()
        .args(["learn", "--particles", "200", "--steps"])
        .arg(bundled("../office/steps.csv"))
        .arg("--out")
        .arg(d.join("learn"))
        .assert()
        .success();
    std::fs::write(d.join("one.csv"), "t,x,y\n1.0,0,0\n").expect("one");
    std::fs::create_dir(d.join("folder")).expect("folder");
    std::fs::write(d.join("wild.toml"), "[motion]\nlength_sigma = 1e308\n").expect("wild");
    // An IMU at rest logged in g, and one turning at 100 deg/s logged in deg/s.
    let imu = |row: &dyn Fn(f64) -> String| {
        let rows: String = (0..300).map(|i| row(f64::from(i) * 0.01)).collect();
        format!("t,ax,ay,az,gx,gy,gz\n{rows}")
    };
    std::fs::write(
        d.join("in_g.csv"),
        imu(&|t| format!("{t},0.01,0.02,1.0,0,0,0\n")),
    )
    .expect("g");
    std::fs::write(
        d.join("in_deg.csv"),
        imu(&|t| format!("{t},0,0,9.8,0,0,100\n")),
    )
    .expect("deg");

    let p = |name: &str| d.join(name).display().to_string();
    let s = |x: &str| x.to_owned();
    let track = |plan: &str, extra: &[&str]| {
        let mut a = vec![s("track"), s("--plan"), p(plan), s("--steps")];
        a.push(steps.display().to_string());
        a.extend(extra.iter().map(|x| s(x)));
        a
    };
    let map = p("learn/map.geojson");
    let cases = [
        Case {
            name: "a surface 1e308 m high",
            args: track("high.geojson", &[]),
            fails: true,
            says: &["high.geojson", "z = 1e308", "±1000 m"],
        },
        Case {
            name: "a plan of a few millimetres",
            args: track("tiny.geojson", &[]),
            fails: true,
            says: &["tiny.geojson", "is it in metres"],
        },
        Case {
            name: "a polygon of 20,001 vertices",
            args: track("dense.geojson", &[]),
            fails: true,
            says: &["dense.geojson", "20001 vertices", "10000", "simplify it"],
        },
        Case {
            name: "a plan 16 km wide",
            args: track("huge.geojson", &[]),
            fails: true,
            says: &["huge.geojson", "at most 10000 m"],
        },
        Case {
            name: "a plan 111 km from its origin",
            args: track("far.geojson", &[]),
            fails: true,
            says: &["far.geojson", "km from its frame's origin"],
        },
        Case {
            name: "a surface given twice",
            args: track("twice.geojson", &[]),
            fails: true,
            says: &["twice.geojson", "same polygon"],
        },
        Case {
            name: "a plan with a byte-order mark",
            args: track("bom.geojson", &["--config", &p("cap.toml")]),
            fails: false,
            says: &[],
        },
        Case {
            name: "the prior capped before KLD is met",
            args: track("bom.geojson", &["--config", &p("cap.toml")]),
            fails: false,
            says: &["warning", "kld.max_particles = 20000"],
        },
        Case {
            name: "a CSV column given twice",
            args: vec![s("learn"), s("--steps"), p("two_t.csv")],
            fails: true,
            says: &["two_t.csv:1", "`t` appears twice"],
        },
        Case {
            name: "merge with every weight 0",
            args: vec![
                s("merge"),
                map.clone(),
                map.clone(),
                s("--weights"),
                s("0,0"),
            ],
            fails: true,
            says: &["all 0"],
        },
        Case {
            name: "merge of one map twice",
            args: vec![s("merge"), map.clone(), map.clone()],
            fails: false,
            says: &["warning", "given twice"],
        },
        Case {
            name: "a dz column with every cell empty on a plan of several floors",
            args: vec![
                s("track"),
                s("--plan"),
                bundled("floor.geojson").display().to_string(),
                s("--steps"),
                p("empty_dz.csv"),
            ],
            fails: true,
            says: &["no `dz` column", "3 levels"],
        },
        Case {
            name: "merge onto one of its inputs",
            args: vec![
                s("merge"),
                map.clone(),
                map.clone(),
                s("--out"),
                map.clone(),
            ],
            fails: true,
            says: &["is the input map", "another file"],
        },
        Case {
            name: "merge into a folder of other files (the inputs')",
            args: vec![s("merge"), map.clone(), s("--out"), p("")],
            fails: true,
            says: &["other files in it", "new or empty folder"],
        },
        Case {
            name: "an --out that is a file",
            args: vec![
                s("learn"),
                s("--particles"),
                s("100"),
                s("--out"),
                p("one.csv"),
            ],
            fails: true,
            says: &["one.csv: --out is a file"],
        },
        Case {
            name: "a negative value after a space, and out of range",
            args: vec![s("learn"), s("--cell"), s("-3")],
            fails: true,
            says: &["granularity = -3"],
        },
        Case {
            name: "a model value of 1e308, echoed short",
            args: vec![s("learn"), s("--config"), p("wild.toml")],
            fails: true,
            says: &["motion.length_sigma = 1e308"],
        },
        Case {
            name: "an IMU file in g",
            args: vec![
                s("steps"),
                s("--imu"),
                p("in_g.csv"),
                s("--mount"),
                s("phone"),
            ],
            fails: true,
            says: &["in_g.csv", "in g?", "--accel-unit g"],
        },
        Case {
            name: "an IMU file in g, said so: read (then no steps while at rest)",
            args: vec![
                s("steps"),
                s("--imu"),
                p("in_g.csv"),
                s("--mount"),
                s("phone"),
                s("--accel-unit"),
                s("g"),
            ],
            fails: true,
            says: &["no steps detected"],
        },
        Case {
            name: "an IMU file in deg/s",
            args: vec![
                s("steps"),
                s("--imu"),
                p("in_deg.csv"),
                s("--mount"),
                s("phone"),
            ],
            fails: true,
            says: &["in_deg.csv:2", "--gyro-unit deg/s"],
        },
        Case {
            name: "rigid alignment on one point",
            args: vec![
                s("eval"),
                s("--truth"),
                p("one.csv"),
                s("--track"),
                p("one.csv"),
                s("--align"),
                s("rigid"),
            ],
            fails: true,
            says: &["at least 3"],
        },
    ];
    for (i, case) in cases.iter().enumerate() {
        run_case(case, &d.join(format!("out-{i}")));
    }
}
