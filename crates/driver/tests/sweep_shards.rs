//! `signorini sweep --shard I/N` and `signorini sweep merge`: shards partition the plan, their
//! merge equals the unsharded sweep (error columns included), foreign, missing, duplicated or
//! damaged shards are refused naming the file and line without writing anything, and `--vtu`
//! writes a ParaView collection whose every file exists and is XML.

mod common;
use common::signorini;

use std::path::{Path, PathBuf};

use signorini::sweep::{read_points, Point};

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("../../fixtures/seed/{name}.toml"))
}

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The plan of every test here: Experiment 2b, two meshes, two backends, two tolerances.
const PLAN: [&str; 6] = [
    "--hmax",
    "0.3,0.2",
    "--backends",
    "clarabel,dual-pgs",
    "--tol",
    "1e-6,1e-9",
];

/// The plan's points in the documented order (hmax coarse to fine, tolerances tightest first,
/// backends as given), written out by hand rather than taken from the code.
const ORDER: [(f64, f64, &str); 8] = [
    (0.3, 1e-9, "clarabel"),
    (0.3, 1e-9, "dual-pgs"),
    (0.3, 1e-6, "clarabel"),
    (0.3, 1e-6, "dual-pgs"),
    (0.2, 1e-9, "clarabel"),
    (0.2, 1e-9, "dual-pgs"),
    (0.2, 1e-6, "clarabel"),
    (0.2, 1e-6, "dual-pgs"),
];

fn run_sweep(scene: &str, extra: &[&str], out: &str, cwd: &Path) -> std::process::Output {
    let mut args = vec!["sweep", scene];
    args.extend(PLAN);
    args.extend(extra);
    args.extend(["--out", out]);
    signorini(&args, cwd)
}

/// Runs shards 1/3, 2/3, 3/3 of the plan on `scene` into `cwd/s1`, `s2`, `s3`.
fn run_shards(scene: &Path, cwd: &Path) {
    for i in 1..=3 {
        let shard = format!("{i}/3");
        let o = run_sweep(
            scene.to_str().expect("UTF-8 path"),
            &["--shard", &shard],
            &format!("s{i}"),
            cwd,
        );
        assert!(o.status.success(), "shard {shard}: {}", stderr(&o));
    }
}

/// Everything of a point but its times and memory (which differ from run to run).
fn without_times(p: &Point) -> Point {
    Point {
        mesh_s: 0.0,
        assemble_s: 0.0,
        solve_s: 0.0,
        floor_s: 0.0,
        ratio_to_floor: 0.0,
        peak_rss_mb: 0.0,
        ..p.clone()
    }
}

fn key(p: &Point) -> (u64, u64, String) {
    (p.hmax.to_bits(), p.tol.to_bits(), p.backend.clone())
}

#[test]
fn merged_shards_equal_the_unsharded_sweep() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let scene = fixture("exp2b");
    let o = run_sweep(scene.to_str().unwrap(), &[], "full", cwd);
    assert!(o.status.success(), "{}", stderr(&o));
    run_shards(&scene, cwd);

    // Shard I holds exactly the points I, I+3, I+6 of ORDER (numbered from 1), errors empty.
    for i in 1..=3usize {
        let points = read_points(&cwd.join(format!("s{i}/sweep.csv"))).unwrap();
        let mut got: Vec<(u64, u64, String)> = points.iter().map(key).collect();
        got.sort();
        let mut want: Vec<(u64, u64, String)> = (i..=ORDER.len())
            .step_by(3)
            .map(|p| {
                let (h, t, b) = ORDER[p - 1];
                (h.to_bits(), t.to_bits(), b.to_string())
            })
            .collect();
        want.sort();
        assert_eq!(got, want, "shard {i}/3");
        assert!(points
            .iter()
            .all(|p| p.error_vs_reference.is_none() && p.error_vs_finest.is_none()));
        let manifest: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(cwd.join(format!("s{i}/shard.json"))).unwrap(),
        )
        .unwrap();
        assert_eq!(manifest["shard"]["index"], i);
        assert_eq!(manifest["shard"]["count"], 3);
        assert_eq!(manifest["complete"], true);
        assert_eq!(
            manifest["scene_hash"].as_str(),
            Some(points[0].scene_hash.as_str())
        );
    }

    let o = signorini(&["sweep", "merge", "s1", "s2", "s3", "--out", "m"], cwd);
    assert!(o.status.success(), "{}", stderr(&o));
    let full = read_points(&cwd.join("full/sweep.csv")).unwrap();
    let merged = read_points(&cwd.join("m/sweep.csv")).unwrap();
    assert_eq!(full.len(), ORDER.len());
    // The same rows in the same (plan) order, apart from times; the error columns — computed
    // from every point — bit for bit equal (they are computed by the same arithmetic from the
    // same numbers, which the CSV and the displacement files carry exactly).
    let full_rows: Vec<Point> = full.iter().map(without_times).collect();
    let merged_rows: Vec<Point> = merged.iter().map(without_times).collect();
    assert_eq!(merged_rows, full_rows);
    for (a, b) in full.iter().zip(&merged) {
        assert!(
            a.error_vs_finest.is_some() && a.error_vs_reference.is_some(),
            "{a:?}"
        );
        assert_eq!(
            a.error_vs_finest.map(f64::to_bits),
            b.error_vs_finest.map(f64::to_bits)
        );
        assert_eq!(
            a.error_vs_reference.map(f64::to_bits),
            b.error_vs_reference.map(f64::to_bits)
        );
    }
    // The looser tolerance is measured against something else than itself.
    assert!(merged.iter().any(|p| p.error_vs_reference.unwrap() > 0.0));
    assert!(cwd.join("m/time_vs_dofs.svg").is_file());
    // Merging again into the same directory needs --overwrite; with it, the same file.
    let before = std::fs::read(cwd.join("m/sweep.csv")).unwrap();
    let o = signorini(&["sweep", "merge", "s3", "s1", "s2", "--out", "m"], cwd);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("--overwrite"), "{}", stderr(&o));
    let o = signorini(
        &[
            "sweep",
            "merge",
            "s3",
            "s1",
            "s2",
            "--out",
            "m",
            "--overwrite",
        ],
        cwd,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read(cwd.join("m/sweep.csv")).unwrap(), before);
}

/// Every entry of `dir` (recursively), for "nothing was written".
fn tree(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).expect("test I/O") {
        let e = e.expect("test I/O");
        if e.file_type().expect("test I/O").is_dir() {
            out.extend(tree(&e.path()));
        } else {
            out.push((e.path(), std::fs::read(e.path()).expect("test I/O")));
        }
    }
    out.sort();
    out
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).expect("test I/O");
    for e in std::fs::read_dir(from).expect("test I/O") {
        let e = e.expect("test I/O");
        if e.file_type().expect("test I/O").is_dir() {
            copy_dir(&e.path(), &to.join(e.file_name()));
        } else {
            std::fs::copy(e.path(), to.join(e.file_name())).expect("test I/O");
        }
    }
}

#[test]
fn merge_refuses_foreign_missing_duplicated_or_damaged_shards() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    run_shards(&fixture("exp2b"), cwd);
    // Shard 2/3 of another scene.
    let o = run_sweep(
        fixture("exp2c").to_str().unwrap(),
        &["--shard", "2/3"],
        "other2",
        cwd,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    // Shard 2/3 timed with other repeats (its times are not the others' kind).
    let o = run_sweep(
        fixture("exp2b").to_str().unwrap(),
        &["--shard", "2/3", "--repeat", "2"],
        "rep2",
        cwd,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    // Shard 3/3 with a damaged row: its line 3 loses its last field.
    copy_dir(&cwd.join("s3"), &cwd.join("bad3"));
    let csv = cwd.join("bad3/sweep.csv");
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    assert!(lines.len() >= 3, "{text}");
    lines[2] = lines[2].rsplit_once(',').unwrap().0.to_string();
    std::fs::write(&csv, lines.join("\n") + "\n").unwrap();
    // Shard 2/3 whose sweep.csv is another scene's (a foreign file under a valid manifest).
    copy_dir(&cwd.join("s2"), &cwd.join("foreign2"));
    std::fs::copy(cwd.join("other2/sweep.csv"), cwd.join("foreign2/sweep.csv")).unwrap();
    // Shard 1/3 whose manifest says it was interrupted.
    copy_dir(&cwd.join("s1"), &cwd.join("cut1"));
    let m = cwd.join("cut1/shard.json");
    let text = std::fs::read_to_string(&m).unwrap();
    std::fs::write(
        &m,
        text.replace("\"complete\": true", "\"complete\": false"),
    )
    .unwrap();
    let line_of = |file: &Path, needle: &str| {
        1 + std::fs::read_to_string(file)
            .unwrap()
            .lines()
            .position(|l| l.contains(needle))
            .unwrap()
    };

    let before = tree(cwd);
    let cases: Vec<(&str, Vec<&str>, String)> = vec![
        (
            "a missing shard",
            vec!["s1", "s3"],
            format!(
                "s1/shard.json: line {}",
                line_of(&cwd.join("s1/shard.json"), "\"shard\"")
            ),
        ),
        (
            "a duplicated shard",
            vec!["s1", "s2", "s2", "s3"],
            format!(
                "s2/shard.json: line {}",
                line_of(&cwd.join("s2/shard.json"), "\"shard\"")
            ),
        ),
        (
            "another scene",
            vec!["s1", "other2", "s3"],
            format!(
                "other2/shard.json: line {}",
                line_of(&cwd.join("other2/shard.json"), "\"scene_hash\"")
            ),
        ),
        (
            "other repeats",
            vec!["s1", "rep2", "s3"],
            format!(
                "rep2/shard.json: line {}: --repeat 2 (vs 1)",
                line_of(&cwd.join("rep2/shard.json"), "\"repeat\"")
            ),
        ),
        (
            "a corrupt line",
            vec!["s1", "s2", "bad3"],
            "bad3/sweep.csv: line 3".to_string(),
        ),
        (
            "a foreign sweep.csv",
            vec!["s1", "foreign2", "s3"],
            "foreign2/sweep.csv: line 2: scene_hash".to_string(),
        ),
        (
            "an interrupted shard",
            vec!["cut1", "s2", "s3"],
            format!("cut1/shard.json: line {}", line_of(&m, "\"complete\"")),
        ),
        (
            "not a shard",
            vec!["s1", "s2", "nowhere"],
            "nowhere/shard.json".to_string(),
        ),
    ];
    for (what, dirs, expect) in cases {
        let mut args = vec!["sweep", "merge"];
        args.extend(&dirs);
        args.extend(["--out", "m"]);
        let o = signorini(&args, cwd);
        assert_eq!(o.status.code(), Some(1), "{what}: {}", stderr(&o));
        assert!(
            stderr(&o).contains(&expect),
            "{what}: want {expect:?} in {}",
            stderr(&o)
        );
        assert!(!cwd.join("m").exists(), "{what}");
        assert_eq!(tree(cwd), before, "{what}");
    }
}

/// An interrupted shard is finished with `--resume` (which refuses another shard's file, naming
/// the line) and then merges like the others.
#[test]
fn an_interrupted_shard_resumes_and_merges() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let scene = fixture("exp2b");
    run_shards(&scene, cwd);
    // Simulate an interruption of shard 1/3 (points 1, 4, 7): its last row is lost and its
    // manifest still says it is running.
    let csv = cwd.join("s1/sweep.csv");
    let text = std::fs::read_to_string(&csv).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 4, "{text}");
    std::fs::write(&csv, lines[..3].join("\n") + "\n").unwrap();
    let m = cwd.join("s1/shard.json");
    let manifest = std::fs::read_to_string(&m).unwrap();
    std::fs::write(
        &m,
        manifest.replace("\"complete\": true", "\"complete\": false"),
    )
    .unwrap();
    let o = signorini(&["sweep", "merge", "s1", "s2", "s3", "--out", "m"], cwd);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("--resume"), "{}", stderr(&o));
    // Resuming it as shard 2/3 is refused: line 2 holds point 1, shard 1's.
    let o = run_sweep(
        scene.to_str().unwrap(),
        &["--shard", "2/3", "--resume"],
        "s1",
        cwd,
    );
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("s1/sweep.csv: line 2: point 1 of the plan belongs to shard 1/3"),
        "{}",
        stderr(&o)
    );
    let o = run_sweep(
        scene.to_str().unwrap(),
        &["--shard", "1/3", "--resume"],
        "s1",
        cwd,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(read_points(&csv).unwrap().len(), 3);
    let o = signorini(&["sweep", "merge", "s1", "s2", "s3", "--out", "m"], cwd);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        read_points(&cwd.join("m/sweep.csv")).unwrap().len(),
        ORDER.len()
    );
}

#[test]
fn bad_shards_are_refused_at_parse() {
    let dir = tempfile::tempdir().unwrap();
    let scene = fixture("exp2b");
    for bad in ["0/3", "4/3", "a/b", "3", "1/0"] {
        let o = run_sweep(scene.to_str().unwrap(), &["--shard", bad], "s", dir.path());
        assert_eq!(o.status.code(), Some(1), "{bad}: {}", stderr(&o));
        let err = stderr(&o);
        assert!(err.contains("--shard") && err.contains(bad), "{bad}: {err}");
        assert!(!dir.path().join("s").exists(), "{bad}");
    }
    // `sweep merge` without directories is a usage error too.
    let o = signorini(&["sweep", "merge"], dir.path());
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
}

/// The XML part of a VTU: all of it, or, for appended raw binary data (not XML text), the part
/// before `<AppendedData`, closed.
fn vtu_xml(bytes: &[u8]) -> String {
    let marker = b"<AppendedData";
    match bytes.windows(marker.len()).position(|w| w == marker) {
        Some(at) => {
            String::from_utf8(bytes[..at].to_vec()).expect("the VTU header is UTF-8") + "</VTKFile>"
        }
        None => String::from_utf8(bytes.to_vec()).expect("the VTU header is UTF-8"),
    }
}

/// Checks `dir/solutions.pvd` against the plan and `dir/sweep.csv`: one `DataSet` per point,
/// timestep = the point's number, every file present and XML.
fn check_collection(dir: &Path) {
    let points = read_points(&dir.join("sweep.csv")).expect("the collection is as written");
    let pvd =
        std::fs::read_to_string(dir.join("solutions.pvd")).expect("the collection is as written");
    let doc = roxmltree::Document::parse(&pvd).expect("the collection is as written");
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "VTKFile");
    assert_eq!(root.attribute("type"), Some("Collection"));
    let sets: Vec<roxmltree::Node> = root
        .descendants()
        .filter(|n| n.has_tag_name("DataSet"))
        .collect();
    assert_eq!(sets.len(), ORDER.len());
    for (k, set) in sets.iter().enumerate() {
        // timestep = the point's number in the plan; the file names its point.
        assert_eq!(
            set.attribute("timestep"),
            Some((k + 1).to_string().as_str())
        );
        let file = set.attribute("file").expect("the collection is as written");
        let (h, t, b) = ORDER[k];
        assert!(
            file.starts_with("solutions/") && file.contains(&format!("_h{h}_{b}_tol{t:e}")),
            "{file}"
        );
        assert!(points
            .iter()
            .any(|p| p.hmax == h && p.tol == t && p.backend == b));
        let bytes = std::fs::read(dir.join(file)).expect("the collection is as written");
        let xml = vtu_xml(&bytes);
        let vtu = roxmltree::Document::parse(&xml).unwrap_or_else(|e| panic!("{file}: {e}"));
        assert_eq!(
            vtu.root_element().attribute("type"),
            Some("UnstructuredGrid")
        );
        // As many points as the mesh has nodes: 2 per free DOF at most, so at least dofs / 2.
        let piece = vtu
            .descendants()
            .find(|n| n.has_tag_name("Piece"))
            .expect("the collection is as written");
        let nodes: usize = piece
            .attribute("NumberOfPoints")
            .expect("the collection is as written")
            .parse()
            .expect("the collection is as written");
        let p = &points[k];
        assert!(
            2 * nodes >= p.dofs,
            "{file}: {nodes} nodes, {} dofs",
            p.dofs
        );
    }
}

#[test]
fn vtu_writes_a_collection_of_every_point() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let scene = fixture("exp2b");
    let o = run_sweep(scene.to_str().unwrap(), &["--vtu"], "v", cwd);
    assert!(o.status.success(), "{}", stderr(&o));
    check_collection(&cwd.join("v"));
    // Shards with --vtu: the merge copies their solutions and lists them all.
    for i in 1..=3 {
        let shard = format!("{i}/3");
        let o = run_sweep(
            scene.to_str().unwrap(),
            &["--vtu", "--shard", &shard],
            &format!("s{i}"),
            cwd,
        );
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let o = signorini(&["sweep", "merge", "s1", "s2", "s3", "--out", "m"], cwd);
    assert!(o.status.success(), "{}", stderr(&o));
    check_collection(&cwd.join("m"));
    // Without --vtu, an overwrite removes the collection (it would name stale files).
    let o = run_sweep(scene.to_str().unwrap(), &["--overwrite"], "v", cwd);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!cwd.join("v/solutions.pvd").exists());
}
