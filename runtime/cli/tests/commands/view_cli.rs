//! `c5 view` and the pages `simulate` writes: the scene data in the page against the
//! kinematics of the CSV the command read (each drawn ball or S joint where the actuator
//! positions put it), the legs' colours against the CSV's forces, limits drawn in the warning
//! colour, decimation to the frame budget, and bad input refused with nothing written. The
//! page in a browser is `tests/browser/view_check.py`'s (run by CI).

use crate::support;

use serde_json::Value;
use std::path::{Path, PathBuf};
use support::{c5, c5_ok};

const HEXAPOD: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/hexapod.toml");
/// The page's drawing resolution (m): its coordinates are rounded to it.
const RESOLUTION: f64 = 1e-7;
const WARNING: &str = "#ff00ff";

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("c5-view-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// The JSON of the page's `<script id="...">` element.
fn embedded(page: &str, id: &str) -> Value {
    let open = format!("<script id=\"{id}\" type=\"application/json\">");
    let start = page.find(&open).expect("the element") + open.len();
    let end = start + page[start..].find("</script>").unwrap();
    serde_json::from_str(&page[start..end]).unwrap()
}

/// The CSV's rows as maps from column name to value.
fn rows(path: &Path) -> Vec<std::collections::HashMap<String, f64>> {
    let mut reader = csv::Reader::from_path(path).unwrap();
    let header: Vec<String> = reader.headers().unwrap().iter().map(String::from).collect();
    reader
        .records()
        .map(|r| {
            let r = r.unwrap();
            header
                .iter()
                .cloned()
                .zip(r.iter().map(|v| v.parse::<f64>().unwrap()))
                .collect()
        })
        .collect()
}

/// A simulated trajectory CSV of `robot` (none: the chapter's C5), and its page by `c5 view`.
fn simulated(name: &str, robot: Option<&str>, frames: &str) -> (PathBuf, Value, Value) {
    let dir = scratch(name);
    let mut args = vec!["simulate", "--out", s(&dir), "--no-view", "--ignore-limits"];
    if let Some(r) = robot {
        args.extend(["--robot", r]);
    }
    c5_ok(&args, "");
    assert!(!dir.join("view.html").exists(), "--no-view wrote a page");
    let csv = dir.join("section9.csv");
    let page = dir.join("page.html");
    let mut args = vec!["view", s(&csv), "--out", s(&page), "--frames", frames];
    if let Some(r) = robot {
        args.extend(["--robot", r]);
    }
    c5_ok(&args, "");
    let text = std::fs::read_to_string(&page).unwrap();
    assert!(text.contains("plotly.js v3"), "plotly.js is embedded");
    assert!(!text.contains("<script src"), "the page loads no script");
    (
        csv,
        embedded(&text, "c5-figure"),
        embedded(&text, "c5-readout"),
    )
}

fn point(trace: &Value, k: usize) -> [f64; 3] {
    ["x", "y", "z"].map(|c| trace[c][k].as_f64().unwrap())
}

/// The rows the page drew: matched by time, the first and the last among them.
fn drawn_rows<'a>(
    csv: &'a [std::collections::HashMap<String, f64>],
    readout: &Value,
) -> Vec<&'a std::collections::HashMap<String, f64>> {
    let shown = readout.as_array().unwrap();
    let picked: Vec<_> = shown
        .iter()
        .map(|r| {
            let t = r["t"].as_f64().unwrap();
            csv.iter()
                .find(|row| row["t"] == t)
                .expect("a row of the file")
        })
        .collect();
    assert_eq!(picked[0]["t"], csv[0]["t"]);
    assert_eq!(picked.last().unwrap()["t"], csv.last().unwrap()["t"]);
    picked
}

/// Each ball on its axis at `A_i + Q_i1 n_i`, with the CSV's `Q_i1` (README, Conventions).
#[test]
fn the_c5_page_puts_each_ball_where_the_csv_says_and_colours_by_force() {
    let (csv, figure, readout) = simulated("c5", None, "40");
    let csv = rows(&csv);
    let frames = figure["frames"].as_array().unwrap();
    assert_eq!((frames.len(), readout.as_array().unwrap().len()), (40, 40));
    let l = 0.2;
    let anchors = [
        [0.0, 0.0, l],
        [0.0, 0.0, -l],
        [l, 0.0, 0.0],
        [-l, 0.0, 0.0],
        [0.0, l, 0.0],
        [0.0, -l, 0.0],
    ];
    let axis = [0, 0, 1, 1, 2, 2];
    for (k, row) in drawn_rows(&csv, &readout).into_iter().enumerate() {
        let data = frames[k]["data"].as_array().unwrap();
        for i in 0..6 {
            let ball = point(&data[i], 1);
            let mut expected = anchors[i];
            expected[axis[i]] += row[&format!("q{}", i + 1)];
            for c in 0..3 {
                assert!(
                    (ball[c] - expected[c]).abs() <= RESOLUTION,
                    "frame {k} leg {i}: {ball:?} {expected:?}"
                );
            }
            let gamma = row[&format!("gamma{}", i + 1)];
            assert_eq!(readout[k]["gamma"][i].as_f64().unwrap(), gamma);
            let colour = data[i]["line"]["color"].as_str().unwrap();
            assert_eq!(colour, readout[k]["colours"][i].as_str().unwrap());
        }
    }
    assert_colours_follow_forces(&readout);
}

/// Warmer for a larger force, across every leg and frame: red minus blue grows with `Γ`.
fn assert_colours_follow_forces(readout: &Value) {
    let mut pairs: Vec<(f64, i64)> = Vec::new();
    for r in readout.as_array().unwrap() {
        for i in 0..6 {
            let c = r["colours"][i].as_str().unwrap();
            assert_ne!(c, WARNING);
            let channel = |k: usize| i64::from_str_radix(&c[1 + 2 * k..3 + 2 * k], 16).unwrap();
            pairs.push((r["gamma"][i].as_f64().unwrap(), channel(0) - channel(2)));
        }
    }
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    // Each channel is rounded on its own: red minus blue may step back by one.
    let back = pairs.windows(2).find(|w| w[1].1 < w[0].1 - 1);
    assert!(back.is_none(), "colours not ordered by force: {back:?}");
    assert!(
        pairs.last().unwrap().1 - pairs[0].1 > 100,
        "one colour for every force"
    );
}

/// Each S joint at the length the CSV's actuator position gives: `|B_i - A_i| + o_i = q_i`.
#[test]
fn the_hexapod_page_puts_each_leg_at_the_csvs_length() {
    let (csv, figure, readout) = simulated("hexapod", Some(HEXAPOD), "25");
    let csv = rows(&csv);
    let robot =
        c5_robot::GoughStewart::from_toml(&std::fs::read_to_string(HEXAPOD).unwrap(), HEXAPOD)
            .unwrap();
    let frames = figure["frames"].as_array().unwrap();
    for (k, row) in drawn_rows(&csv, &readout).into_iter().enumerate() {
        let data = frames[k]["data"].as_array().unwrap();
        for (i, leg) in robot.legs.iter().enumerate() {
            let (a, b) = (point(&data[i], 0), point(&data[i], 1));
            for (drawn, given) in a.iter().zip(leg.base) {
                assert!((drawn - given).abs() <= RESOLUTION);
            }
            let length = (0..3).map(|c| (b[c] - a[c]).powi(2)).sum::<f64>().sqrt();
            let q = row[&format!("q{}", i + 1)];
            assert!(
                (length + leg.encoder_offset - q).abs() <= 4.0 * RESOLUTION,
                "frame {k} leg {i}: {length} + {} vs {q}",
                leg.encoder_offset
            );
        }
    }
}

/// A robot file whose stroke the move crosses: those legs in the warning colour, named in the
/// readout; the forces' colours on the file's force limit.
#[test]
fn legs_past_a_limit_are_drawn_in_the_warning_colour() {
    let robot = scratch("limits.toml");
    std::fs::write(&robot, "[limits]\nstroke = [-0.05, 0.05]\nforce = 500\n").unwrap();
    let (csv, figure, readout) = simulated("limits", Some(s(&robot)), "30");
    let csv = rows(&csv);
    let frames = figure["frames"].as_array().unwrap();
    let mut flagged = 0;
    for (k, row) in drawn_rows(&csv, &readout).into_iter().enumerate() {
        for i in 0..6 {
            let q: f64 = row[&format!("q{}", i + 1)];
            let colour = frames[k]["data"][i]["line"]["color"].as_str().unwrap();
            let named = readout[k]["warnings"].as_array().unwrap().iter().any(|w| {
                w.as_str()
                    .unwrap()
                    .starts_with(&format!("leg {}: stroke", i + 1))
            });
            assert_eq!(q.abs() > 0.05, colour == WARNING, "frame {k} leg {i}");
            assert_eq!(q.abs() > 0.05, named);
            flagged += usize::from(named);
        }
    }
    assert!(flagged > 0, "the move never crosses the stroke");
    let page = std::fs::read_to_string(scratch("limits").join("page.html")).unwrap();
    assert!(page.contains("±500.0 N (the robot file's force limit)"));
}

#[test]
fn simulate_writes_the_page_beside_its_plots() {
    let dir = scratch("simulate");
    let out = c5_ok(&["simulate", "--out", s(&dir), "--view-frames", "20"], "");
    let page = dir.join("view.html");
    assert!(String::from_utf8_lossy(&out.stdout).contains("view.html"));
    let readout = embedded(&std::fs::read_to_string(page).unwrap(), "c5-readout");
    assert_eq!(readout.as_array().unwrap().len(), 20);
}

#[test]
fn bad_input_is_refused_and_writes_nothing() {
    let page = scratch("never.html");
    let missing = scratch("missing.csv");
    let no_pose = scratch("no_pose.csv");
    std::fs::write(&no_pose, "t,alpha,beta,gamma,xc,yc\n0,0,0,0,0,0\n").unwrap();
    let unreachable = scratch("singular.csv");
    std::fs::write(
        &unreachable,
        "t,alpha,beta,gamma,xc,yc,zc\n0,0,0,0,0,0,0\n1,0,1.5707963267948966,0,0,0,0\n",
    )
    .unwrap();
    for (file, says) in [
        (&missing, "missing.csv"),
        (&no_pose, "missing column(s) zc"),
        (&unreachable, "singular.csv:3"),
    ] {
        let out = c5(&["view", s(file), "--out", s(&page)], "");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && err.contains(says), "{err}");
        assert!(!page.exists());
    }
    let out = c5(&["view", s(&missing), "--frames", "1"], "");
    assert!(!out.status.success());
}

/// The Delta's page, from its robot file and the CSV alone: each upper arm from its motor `A_i`
/// at the CSV's angle `θ_i = q_i - o_i` (`E_i = A_i + c_i (cos θ_i h_i + sin θ_i k_i)`), each
/// parallelogram's rods `L_i` long from `E_i ± (w_i/2) r_i` to `C + p_i ± (w_i/2) r_i`; its
/// torques in N·m, three to a frame.
#[test]
fn the_delta_page_draws_each_arm_at_the_csvs_angle_and_its_rods_at_their_length() {
    const DELTA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/delta.toml");
    let (csv, figure, readout) = simulated("delta", Some(DELTA), "15");
    let csv = rows(&csv);
    let robot =
        c5_robot::Delta::from_toml(&std::fs::read_to_string(DELTA).unwrap(), DELTA).unwrap();
    let frames = figure["frames"].as_array().unwrap();
    let near = |a: [f64; 3], b: [f64; 3]| (0..3).all(|k| (a[k] - b[k]).abs() <= 4.0 * RESOLUTION);
    let along = |p: [f64; 3], s: f64, v: [f64; 3]| -> [f64; 3] {
        core::array::from_fn(|k| p[k] + s * v[k])
    };
    for (k, row) in drawn_rows(&csv, &readout).into_iter().enumerate() {
        let data = frames[k]["data"].as_array().unwrap();
        assert_eq!(readout[k]["gamma"].as_array().unwrap().len(), 3);
        let centre = ["xc", "yc", "zc"].map(|c| row[c]);
        for (i, arm) in robot.arms.iter().enumerate() {
            let path: Vec<[f64; 3]> = (0..7).map(|j| point(&data[i], j)).collect();
            let (r, h, kk) = arm.axes();
            let theta = row[&format!("q{}", i + 1)] - arm.encoder_offset;
            let dir: [f64; 3] = core::array::from_fn(|c| theta.cos() * h[c] + theta.sin() * kk[c]);
            let elbow = along(arm.base, arm.crank.length, dir);
            let ball: [f64; 3] = core::array::from_fn(|c| centre[c] + arm.platform[c]);
            let w = arm.rod.separation.unwrap();
            let expected = [
                arm.base,
                elbow,
                along(elbow, -0.5 * w, r),
                along(ball, -0.5 * w, r),
                along(ball, 0.5 * w, r),
                along(elbow, 0.5 * w, r),
                elbow,
            ];
            for (j, (drawn, want)) in path.iter().zip(expected).enumerate() {
                assert!(
                    near(*drawn, want),
                    "frame {k} arm {i} point {j}: {drawn:?} {want:?}"
                );
            }
            let rod = (0..3)
                .map(|c| (path[3][c] - path[2][c]).powi(2))
                .sum::<f64>()
                .sqrt();
            assert!((rod - arm.rod.length).abs() <= 4.0 * RESOLUTION, "{rod}");
        }
    }
    let page = std::fs::read_to_string(scratch("delta").join("page.html")).unwrap();
    assert!(page.contains("N·m ("), "the torques' unit");
}
