//! Tests of the sweep plots: CSV parsing, slope fitting and the four SVGs.

use std::fmt::Write as _;
use std::path::Path;

use signorini::plots::{fit_slope, plot_sweep, read_sweep, SweepRow};

const HEADER: &str = "hmax,dofs,constraints,backend,tol,status,iterations,mesh_s,assemble_s,\
solve_s,floor_s,ratio_to_floor,error_vs_reference,error_vs_finest,max_displacement,peak_rss_mb,\
max_penetration,stationarity,complementarity";

const BACKENDS: [(&str, f64, f64); 3] = [
    ("clarabel", 2e-6, 1.15),
    ("osqp", 5e-6, 1.3),
    ("dual-pgs", 1e-7, 1.6),
];
const SIZES: [(f64, usize); 4] = [(0.2, 200), (0.1, 800), (0.05, 3200), (0.025, 12800)];
const TOLS: [f64; 2] = [1e-6, 1e-9];

/// 3 backends × 4 sizes × 2 tolerances; osqp at the finest mesh and tight tolerance hits its
/// iteration limit; clarabel's tight-tolerance error at the finest mesh is exactly 0 (it is the
/// reference).  Floats are written in both `{:e}` and plain form, `error_vs_finest` is empty at
/// the finest mesh.
fn synthetic_csv() -> String {
    let mut s = format!("{HEADER}\n");
    for (backend, c, p) in BACKENDS {
        for (hmax, dofs) in SIZES {
            for tol in TOLS {
                let n = dofs as f64;
                let tight = tol < 1e-7;
                let solve = c * n.powf(p) * if tight { 1.5 } else { 1.0 };
                let floor = 1e-6 * n.powf(1.1);
                let finest = hmax == 0.025;
                let status = if backend == "osqp" && finest && tight {
                    "max-iterations"
                } else {
                    "solved"
                };
                let err = if backend == "clarabel" && finest && tight {
                    0.0
                } else {
                    tol * 10.0 * (1.0 + p)
                };
                let iters = (20.0 * n.powf(p - 1.0)).round() as usize;
                let err_finest = if finest {
                    String::new()
                } else {
                    format!("{:e}", hmax * hmax)
                };
                writeln!(
                    s,
                    "{hmax},{dofs},{},{backend},{tol:e},{status},{iters},0.01,{:e},{solve:e},\
                     {floor},{},{err:e},{err_finest},1.5e-3,12.5,1e-12,1e-9,1e-10",
                    dofs / 20,
                    0.002 * n / 1000.0,
                    solve / floor
                )
                .expect("writing to a String cannot fail");
            }
        }
    }
    s
}

fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).expect("cannot write the test CSV");
    path
}

#[test]
fn reads_the_synthetic_sweep() {
    let dir = tempfile::tempdir().unwrap();
    let rows = read_sweep(&write(dir.path(), "sweep.csv", &synthetic_csv())).unwrap();
    assert_eq!(rows.len(), 24);
    let r = &rows[0];
    assert_eq!((r.hmax, r.dofs, r.constraints), (0.2, 200, 10));
    assert_eq!(
        (r.backend.as_str(), r.tol, r.status.as_str()),
        ("clarabel", 1e-6, "solved")
    );
    assert!(r.error_vs_finest.is_some());
    let finest: Vec<&SweepRow> = rows.iter().filter(|r| r.hmax == 0.025).collect();
    assert!(finest.iter().all(|r| r.error_vs_finest.is_none()));
    assert_eq!(
        rows.iter().filter(|r| r.status == "max-iterations").count(),
        1
    );
}

#[test]
fn writes_four_readable_svgs() {
    let dir = tempfile::tempdir().unwrap();
    let rows = read_sweep(&write(dir.path(), "sweep.csv", &synthetic_csv())).unwrap();
    let out = dir.path().join("plots");
    let paths = plot_sweep(&rows, &out, "synthetic sweep").unwrap();
    // To look at the plots: SIGNORINI_PLOTS_DIR=/some/dir cargo test --test plots
    if let Some(keep) = std::env::var_os("SIGNORINI_PLOTS_DIR") {
        plot_sweep(&rows, Path::new(&keep), "synthetic sweep").unwrap();
    }
    let names: Vec<String> = paths
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        names,
        [
            "time_vs_dofs.svg",
            "ratio_vs_dofs.svg",
            "work_precision.svg",
            "iterations_vs_dofs.svg"
        ]
    );
    for path in &paths {
        assert!(path.starts_with(&out));
        let svg = std::fs::read_to_string(path).unwrap();
        let doc = roxmltree::Document::parse(&svg)
            .unwrap_or_else(|e| panic!("{} is not XML: {e}", path.display()));
        let text: String = doc
            .descendants()
            .filter_map(|n| n.text())
            .collect::<Vec<_>>()
            .join("\n");
        for (backend, _, _) in BACKENDS {
            assert!(
                text.contains(backend),
                "{} lacks {backend}'s legend entry",
                path.display()
            );
        }
        // The non-solved point shows as a hollow marker, explained in the legend.
        assert!(text.contains("hollow: not solved"), "{}", path.display());
    }
    for name in [
        "time_vs_dofs.svg",
        "ratio_vs_dofs.svg",
        "iterations_vs_dofs.svg",
    ] {
        let svg = std::fs::read_to_string(out.join(name)).unwrap();
        for (backend, _, _) in BACKENDS {
            assert!(
                svg.contains(&format!("{backend} (slope ")),
                "{name}: {backend}"
            );
        }
    }
    let time = std::fs::read_to_string(&paths[0]).unwrap();
    // The tight-tolerance rows of clarabel and dual-pgs follow exact power laws in DOFs.
    assert!(time.contains("clarabel (slope 1.15)"));
    assert!(time.contains("dual-pgs (slope 1.60)"));
    assert!(time.contains("floor (slope 1.10)"));
    assert!(time.contains("stroke-dasharray") || time.matches("<polyline").count() > 10);
    let wp = std::fs::read_to_string(&paths[2]).unwrap();
    assert!(
        !wp.contains("slope"),
        "work–precision has no power-law slope"
    );
    assert!(wp.contains("hmax = 0.025 (12800 DOFs)"));
    assert!(wp.contains("error 0 drawn at 1e-16"));
    let ratio = std::fs::read_to_string(&paths[1]).unwrap();
    assert!(ratio.contains("floor (ratio 1)"));
}

#[test]
fn single_tolerance_skips_work_precision() {
    let dir = tempfile::tempdir().unwrap();
    let csv: String = synthetic_csv()
        .lines()
        .filter(|l| l.split(',').nth(4) != Some("1e-9"))
        .map(|l| format!("{l}\n"))
        .collect();
    let rows = read_sweep(&write(dir.path(), "sweep.csv", &csv)).unwrap();
    assert_eq!(rows.len(), 12);
    let paths = plot_sweep(&rows, dir.path(), "").unwrap();
    assert_eq!(paths.len(), 3);
    assert!(!dir.path().join("work_precision.svg").exists());
}

#[test]
fn fit_slope_recovers_power_laws() {
    for p in [-2.0, -0.5, 0.0, 1.0, 1.08, 1.5, 3.0] {
        let pts: Vec<(f64, f64)> = [10.0, 37.0, 400.0, 12345.0, 1e6]
            .iter()
            .map(|&x: &f64| (x, 3.7e-4 * x.powf(p)))
            .collect();
        let s = fit_slope(&pts).unwrap();
        assert!((s - p).abs() < 1e-12, "p = {p}: fitted {s}");
    }
    // Unusable points are ignored.
    let pts = [
        (1.0, 2.0),
        (0.0, 5.0),
        (4.0, 8.0),
        (f64::NAN, 1.0),
        (2.0, -1.0),
    ];
    assert!((fit_slope(&pts).unwrap() - 1.0).abs() < 1e-12);
    assert_eq!(fit_slope(&[]), None);
    assert_eq!(fit_slope(&[(3.0, 1.0)]), None);
    assert_eq!(fit_slope(&[(3.0, 1.0), (3.0, 2.0), (3.0, 9.0)]), None);
}

#[test]
fn malformed_line_names_file_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let mut lines: Vec<String> = synthetic_csv().lines().map(String::from).collect();
    // Line 5 of the file (header = line 1): DOFs that are not an integer.
    lines[4] = lines[4].replacen(",800,", ",eight hundred,", 1);
    assert!(lines[4].contains("eight hundred"));
    let path = write(dir.path(), "bad.csv", &lines.join("\n"));
    let err = read_sweep(&path).unwrap_err().to_string();
    assert!(err.contains("bad.csv"), "{err}");
    assert!(err.contains("line 5"), "{err}");
    assert!(err.contains("dofs"), "{err}");

    // A row with a missing field.
    let mut lines: Vec<String> = synthetic_csv().lines().map(String::from).collect();
    lines[3] = "0.1,800,40,osqp".into();
    let path = write(dir.path(), "short.csv", &lines.join("\n"));
    let err = read_sweep(&path).unwrap_err().to_string();
    assert!(err.contains("short.csv") && err.contains("line 4"), "{err}");

    // A missing file.
    let err = read_sweep(&dir.path().join("absent.csv"))
        .unwrap_err()
        .to_string();
    assert!(err.contains("absent.csv"), "{err}");
}

#[test]
fn empty_data_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("plots");
    assert!(plot_sweep(&[], &out, "empty").unwrap().is_empty());
    assert!(!out.exists());

    // Header only.
    let rows = read_sweep(&write(dir.path(), "sweep.csv", &format!("{HEADER}\n"))).unwrap();
    assert!(rows.is_empty());
    assert!(plot_sweep(&rows, &out, "").unwrap().is_empty());

    // Rows without anything drawable on log axes (zero times, zero iterations, no errors).
    let csv = format!(
        "{HEADER}\n0.1,800,40,osqp,1e-6,solved,0,0,0,0,0,,,,0,0,0,0,0\n\
         0.1,800,40,osqp,1e-8,inaccurate,0,0,0,0,0,,,,0,0,0,0,0\n"
    );
    let rows = read_sweep(&write(dir.path(), "zeros.csv", &csv)).unwrap();
    assert_eq!(rows.len(), 2);
    assert!(rows[0].floor_s.abs() < 1e-300 && rows[0].ratio_to_floor.is_nan());
    assert!(plot_sweep(&rows, &out, "").unwrap().is_empty());
    assert!(!out.exists());
}

#[test]
fn any_title_and_backend_name_give_well_formed_svgs() {
    // A control character (forbidden in XML 1.0) and every character XML escapes.
    let nasty = "\u{1}<&\"'>";
    let read_back = "\u{FFFD}<&\"'>";
    let dir = tempfile::tempdir().unwrap();
    let csv = synthetic_csv().replace(
        ",osqp,",
        &format!(",\"osqp {}\",", nasty.replace('"', "\"\"")),
    );
    let rows = read_sweep(&write(dir.path(), "sweep.csv", &csv)).unwrap();
    assert!(rows.iter().any(|r| r.backend == format!("osqp {nasty}")));
    let out = dir.path().join("plots");
    let paths = plot_sweep(&rows, &out, &format!("title {nasty}")).unwrap();
    assert_eq!(paths.len(), 4);
    for path in &paths {
        let svg = std::fs::read_to_string(path).unwrap();
        let doc = roxmltree::Document::parse(&svg)
            .unwrap_or_else(|e| panic!("{} is not XML: {e}", path.display()));
        let texts: Vec<&str> = doc
            .descendants()
            .filter_map(|n| n.text())
            .map(str::trim)
            .collect();
        assert!(
            texts
                .iter()
                .any(|t| t.starts_with(&format!("title {read_back}: "))),
            "{}: {texts:?}",
            path.display()
        );
        assert!(
            texts
                .iter()
                .any(|t| t.starts_with(&format!("osqp {read_back}"))),
            "{}: {texts:?}",
            path.display()
        );
    }
}

#[test]
fn plots_are_one_set_and_stale_ones_go() {
    let dir = tempfile::tempdir().unwrap();
    let rows = read_sweep(&write(dir.path(), "sweep.csv", &synthetic_csv())).unwrap();
    let out = dir.path().join("plots");
    assert_eq!(plot_sweep(&rows, &out, "").unwrap().len(), 4);
    // One tolerance: no work–precision plot, and the earlier one no longer belongs to the data.
    let one_tol: Vec<_> = rows.iter().filter(|r| r.tol == 1e-6).cloned().collect();
    assert_eq!(plot_sweep(&one_tol, &out, "").unwrap().len(), 3);
    let mut names: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "iterations_vs_dofs.svg",
            "ratio_vs_dofs.svg",
            "time_vs_dofs.svg"
        ]
    );
}
