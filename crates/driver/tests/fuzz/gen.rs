//! The scene generator: scenes as TOML text, valid, near-degenerate and broken.
//!
//! A scene is built as a list of sections of `key = value` entries (so that a mutation can
//! remove, add, lengthen, shorten or poison one entry), then rendered as TOML.

use proptest::prelude::*;
use proptest::sample::{select, Index};

use signorini::backends::BackendKind;

/// One `key = value` line.
#[derive(Debug, Clone)]
pub struct Entry {
    /// The key.
    pub key: &'static str,
    /// The value, already TOML.
    pub value: String,
    /// The scene is invalid without it.
    pub required: bool,
    /// An array whose length the contract fixes (so one more or one less element is an error).
    pub fixed_array: bool,
    /// Holds numbers (a `nan` may replace one).
    pub numeric: bool,
}

impl Entry {
    fn new(key: &'static str, value: String) -> Self {
        Self {
            key,
            value,
            required: true,
            fixed_array: false,
            numeric: false,
        }
    }
    fn optional(mut self) -> Self {
        self.required = false;
        self
    }
    fn array(mut self) -> Self {
        self.fixed_array = true;
        self
    }
    fn num(mut self) -> Self {
        self.numeric = true;
        self
    }
}

/// A `[table]` or `[[array]]` of entries (`header` empty for the top level).
#[derive(Debug, Clone)]
pub struct Section {
    /// `"[model]"`, `"[[body]]"`, … or `""`.
    pub header: &'static str,
    /// Its lines.
    pub entries: Vec<Entry>,
}

/// A change that makes a scene broken (or, for `ControlChar`, merely hostile).
#[derive(Debug, Clone)]
pub enum Mutation {
    /// Nothing.
    None,
    /// Drop one entry.
    RemoveKey(Index),
    /// Add a key no table knows.
    UnknownKey(Index),
    /// One element more (`true`) or fewer in a fixed-length array.
    WrongLength(Index, bool),
    /// Replace a number with `nan`.
    Nan(Index),
    /// Refer to a body that does not exist.
    UnknownBody(Index),
    /// Put a control character into a body name (every reference renamed consistently).
    ControlChar(Index, char),
}

/// What a mutation broke: the scene must be refused, naming `key`.
#[derive(Debug, Clone)]
pub struct Broken {
    /// What breaks the scene, the key backticked (`` nan in `young` ([[body]]) ``).
    pub why: String,
    /// The key the mutation broke (removed, added, lengthened, poisoned or pointed elsewhere):
    /// the refusal must name it.
    pub key: String,
    /// The scene before the mutation, when known (a generated case): a refusal that does not
    /// name `key` is still right when this scene is refused with the same message, i.e. for a
    /// fault the scene had before it was broken (saved replays carry none).
    pub clean: Option<String>,
}

impl Broken {
    /// A broken scene known by its `why` alone (a saved replay): the key is its first
    /// backticked word.
    pub fn from_why(why: &str) -> Self {
        let key = why.split('`').nth(1).unwrap_or("").to_string();
        Broken {
            why: why.to_string(),
            key,
            clean: None,
        }
    }
}

/// A generated test case.
#[derive(Debug, Clone)]
pub struct Case {
    /// The scene file.
    pub toml: String,
    /// Files the scene refers to (Gmsh meshes), as (name relative to the scene, text).
    pub files: Vec<(String, String)>,
    /// When the scene is broken and must be refused: what breaks it.
    pub must_refuse: Option<Broken>,
    /// Backend to solve with.
    pub backend: BackendKind,
    /// Nothing is loaded or prescribed and no two bodies overlap: the answer is u = 0.
    pub at_rest: bool,
}

fn f(v: f64) -> String {
    // `{:?}` is valid TOML for every finite f64 (`1e300`, `0.5`, `-2.0`).
    format!("{v:?}")
}

fn arr(v: &[f64]) -> String {
    format!(
        "[{}]",
        v.iter().map(|x| f(*x)).collect::<Vec<_>>().join(", ")
    )
}

fn log_uniform(lo: f64, hi: f64) -> impl Strategy<Value = f64> {
    (lo.log10()..hi.log10()).prop_map(|e| 10f64.powf(e))
}

/// Young's modulus: ordinary, or from 1e-200 to 1e300, zero or negative.
fn young() -> impl Strategy<Value = f64> {
    prop_oneof![
        8 => log_uniform(1e-3, 1e3),
        2 => select(vec![1e-200, 1e-100, 1e-30, 1e30, 1e100, 1e200, 1e300, 1.7e308]),
        1 => select(vec![0.0, -1.0, f64::MIN_POSITIVE]),
    ]
}

/// Poisson's ratio: ordinary, or close to 0.5 and −1, or out of range.
fn poisson() -> impl Strategy<Value = f64> {
    prop_oneof![
        8 => 0.0..0.45f64,
        2 => select(vec![0.49, 0.4999999, 0.499999999999, -0.9999999, -0.999999999999, -0.5]),
        1 => select(vec![0.5, -1.0, 0.7, -1.5]),
    ]
}

/// A traction component: ordinary or up to 1e200.
fn traction() -> impl Strategy<Value = f64> {
    prop_oneof![
        8 => (-1.0..1.0f64).prop_map(|t| t * 1e-3),
        2 => select(vec![1e-200, -1e-100, -1e30, 1e100, -1e200, 1e200, -1e300]),
        1 => Just(0.0),
    ]
}

/// A prescribed displacement: usually zero, sometimes up to 1e300.
fn dirichlet_value() -> impl Strategy<Value = f64> {
    prop_oneof![
        8 => Just(0.0),
        3 => -0.1..0.1f64,
        1 => select(vec![1e-200, -1e10, 1e100, 1e300, -1e300]),
    ]
}

/// hmax as a fraction of the body's smaller side, or extreme absolute values.
#[derive(Debug, Clone, Copy)]
enum Hmax {
    Relative(f64),
    Absolute(f64),
}

fn hmax() -> impl Strategy<Value = Hmax> {
    prop_oneof![
        10 => (0.15..0.7f64).prop_map(Hmax::Relative),
        1 => (0.01..0.05f64).prop_map(Hmax::Relative),
        2 => select(vec![1e-300, 1e-12, 1e300, 0.0, -1.0]).prop_map(Hmax::Absolute),
    ]
}

/// Unit scale of a body: mostly 1, sometimes millimetres or kilometres against the others.
fn unit() -> impl Strategy<Value = f64> {
    prop_oneof![10 => Just(1.0), 1 => select(vec![1e-3, 1e3, 1e-9, 1e9])]
}

/// Vertical gap between a body and the one below it (in units of the lower body's height).
fn gap() -> impl Strategy<Value = f64> {
    prop_oneof![
        10 => Just(0.0),
        2 => 0.001..0.1f64,
        2 => -0.5..-1e-3f64,
        1 => select(vec![1e-12, -1e-12, 1e6, -1e6]),
    ]
}

#[derive(Debug, Clone)]
struct BodyParams {
    width: f64,
    height: f64,
    sliver: bool,
    unit: f64,
    gap: f64,
    shift: f64,
    hmax: Hmax,
    q1: bool,
    young: f64,
    poisson: f64,
    support: u8,
    /// A `[[body.refine]]` over the body's bottom tenth, its hmax this fraction of the body's.
    refine: Option<f64>,
    /// The mesh read from a Gmsh file the generator writes (`mesh = "bI.msh"`, MSH 4.1 ASCII,
    /// triangles or, with `q1`, quadrilaterals) instead of `polygon`; `true`: every element
    /// listed clockwise (the reader turns them all).
    gmsh: Option<bool>,
    /// A cap (frictional cases, the top body only): the bottom edge is a circular arc of this
    /// half-angle (radians), drawn as a polygon of this many chords, its lowest point where the
    /// block's bottom would be.
    cap: Option<Cap>,
}

/// A cap's arc: `chords` chords over a half-angle `theta` (radians).
#[derive(Debug, Clone, Copy)]
struct Cap {
    chords: usize,
    theta: f64,
}

impl Cap {
    /// The arc's radius and sag (its height above its lowest point at the ends) for width `w`.
    fn radius_sag(self, w: f64) -> (f64, f64) {
        let r = 0.5 * w / self.theta.sin();
        (r, r * (1.0 - self.theta.cos()))
    }
}

fn body_params() -> impl Strategy<Value = BodyParams> {
    (
        (0.3..3.0f64, 0.3..2.0f64, prop::bool::weighted(0.08), unit()),
        (gap(), -0.5..0.5f64, hmax(), prop::bool::weighted(0.3)),
        (
            young(),
            poisson(),
            0u8..4,
            prop::option::weighted(0.25, select(vec![0.5, 0.2, 0.05])),
            prop::option::weighted(0.15, prop::bool::weighted(0.2)),
        ),
    )
        .prop_map(
            |(
                (width, height, sliver, unit),
                (gap, shift, hmax, q1),
                (young, poisson, support, refine, gmsh),
            )| {
                BodyParams {
                    width,
                    height,
                    sliver,
                    unit,
                    gap,
                    shift,
                    hmax,
                    q1,
                    young,
                    poisson,
                    support,
                    refine,
                    gmsh,
                    cap: None,
                }
            },
        )
}

#[derive(Debug, Clone)]
struct SceneParams {
    bodies: Vec<BodyParams>,
    plane_stress: Option<f64>,
    gravity: Option<f64>,
    load: [f64; 2],
    linear: Option<[f64; 2]>,
    values: [f64; 2],
    contact_region: bool,
    slave: Option<bool>,
    probe: bool,
    mortar: bool,
    /// Friction on every pair, named loads and `[[step]]`s (a frictional case), or none.
    friction: Option<FrictionParams>,
}

fn scene_params() -> impl Strategy<Value = SceneParams> {
    (
        prop::collection::vec(body_params(), 1..=3),
        (
            prop::option::weighted(0.2, select(vec![1.0, 0.01, 1e-200, 1e200])),
            prop::option::weighted(0.15, select(vec![-9.81, -1e-3, -1e200, 1e-300])),
        ),
        (traction(), traction()),
        prop::option::weighted(0.2, (traction(), traction()).prop_map(|(a, b)| [a, b])),
        (dirichlet_value(), dirichlet_value()),
        (
            prop::bool::weighted(0.6),
            prop::option::weighted(0.3, any::<bool>()),
            any::<bool>(),
            any::<bool>(),
        ),
    )
        .prop_map(
            |(
                bodies,
                (plane_stress, gravity),
                load,
                linear,
                values,
                (contact_region, slave, probe, mortar),
            )| {
                SceneParams {
                    bodies,
                    plane_stress,
                    gravity,
                    load: [load.0, load.1],
                    linear,
                    values: [values.0, values.1],
                    contact_region,
                    slave,
                    probe,
                    mortar,
                    friction: None,
                }
            },
        )
}

/// A frictional pair's law, drawn for every pair of a frictional case.
#[derive(Debug, Clone, Copy)]
enum Law {
    /// Coulomb's μ (`friction = μ`).
    Coulomb(f64),
    /// Tresca's bound as a fraction of the press (`tresca = fraction × press`).
    Tresca(f64),
}

/// What makes a case frictional: the law of its pairs and the top body's load path (pressed in
/// a first `[[step]]`, dragged in a second, sometimes pushed back in a third).
#[derive(Debug, Clone)]
struct FrictionParams {
    law: Law,
    /// The drag against the top pair's capacity: below it (≤ 0.8 of its lower estimate), or
    /// beyond it (≥ 1.3 of its upper bound; see [`friction_loads`]).
    drag: f64,
    /// The drag's direction, ±1.
    sign: f64,
    /// A third step reverses the drag (`drag = -1`).
    push_back: bool,
    /// Increments of each step.
    increments: [u8; 3],
}

fn friction_params() -> impl Strategy<Value = FrictionParams> {
    let increments = || prop_oneof![3 => Just(1u8), 1 => 2..=4u8];
    (
        prop_oneof![
            3 => prop_oneof![
                8 => log_uniform(0.05, 5.0),
                1 => select(vec![0.0, 1e-3, 0.01, 10.0, 100.0]),
            ]
            .prop_map(Law::Coulomb),
            1 => log_uniform(0.05, 5.0).prop_map(Law::Tresca),
        ],
        prop_oneof![3 => 0.0..0.8f64, 2 => 1.3..4.0f64],
        select(vec![1.0, -1.0]),
        prop::bool::weighted(0.35),
        [increments(), increments(), increments()],
    )
        .prop_map(|(law, drag, sign, push_back, increments)| FrictionParams {
            law,
            drag,
            sign,
            push_back,
            increments,
        })
}

/// A frictional scene: [`scene_params`]' bodies (at least two), every pair frictional, the top
/// body a cap in about a third of them (an arc of 2 to 32 chords over a half-angle of 10° to
/// 40°) and floating (held by contact alone) in 60 %, no gravity and no linear traction (the
/// drag is drawn against the press).  In 60 % of them ("tame") the bodies' extreme draws are
/// replaced by ordinary ones (E = 1, ν = 0.3, a relative hmax, unit scale, no sliver, no
/// overlap), so that enough of them are solved for the statics and the law to be judged.
fn frictional_scene_params() -> impl Strategy<Value = SceneParams> {
    (
        (scene_params(), prop::bool::weighted(0.6)),
        friction_params(),
        prop::option::weighted(
            0.35,
            (2usize..=32, 10.0..40.0f64).prop_map(|(chords, deg)| Cap {
                chords,
                theta: deg.to_radians(),
            }),
        ),
        prop::bool::weighted(0.6),
    )
        .prop_map(|((mut p, tame), fr, cap, floating)| {
            if tame {
                for b in &mut p.bodies {
                    if !(1e-3..=1e3).contains(&b.young) {
                        b.young = 1.0;
                    }
                    if !(0.0..=0.45).contains(&b.poisson) {
                        b.poisson = 0.3;
                    }
                    if let Hmax::Absolute(_) = b.hmax {
                        b.hmax = Hmax::Relative(0.3);
                    }
                    b.unit = 1.0;
                    b.sliver = false;
                    b.gap = b.gap.clamp(0.0, 0.1);
                }
                p.load[1] = p.load[1].abs().clamp(1e-5, 1e-2);
            }
            if p.bodies.len() == 1 {
                let copy = p.bodies[0].clone();
                p.bodies.push(copy);
            }
            p.gravity = None;
            p.linear = None;
            let top = p.bodies.len() - 1;
            let b = &mut p.bodies[top];
            if let Some(c) = cap {
                b.cap = Some(c);
                b.gmsh = None;
                b.q1 = false;
            }
            if floating {
                b.support = 0;
            }
            p.friction = Some(fr);
            p
        })
}

/// The press of a frictional case (a downward traction on the top body's top edge): the drawn
/// vertical load's magnitude, 1e-3 when that is zero.
fn press_of(p: &SceneParams) -> f64 {
    match p.load[1].abs() {
        t if t > 0.0 => t,
        _ => 1e-3,
    }
}

/// The loads of a frictional case: `press` and `drag` on the top body's top edge, and the
/// `[[step]]`s: press; press and drag; sometimes press and the drag reversed.
///
/// The drag d (a traction over the top edge of width w, so a force T = d w, against the press
/// N = p w) is drawn against the top pair's capacity. Below: a fraction of a lower estimate —
/// Coulomb μ N; Tresca s × the overlap of the two bodies. Beyond: at least 1.3 × an upper bound
/// — with the rows' normals within θ of the vertical (θ the cap's half-angle, 0 for a block),
/// Coulomb tan(atan μ + θ) N (when atan μ + θ < 80°, else the drag stays below), Tresca
/// (N + S) tan θ + S with S = s × the longer of the lower body's top and the top body's bottom.
fn friction_loads(
    p: &SceneParams,
    fr: &FrictionParams,
    rects: &[[f64; 4]],
    names: &[String],
    out: &mut Vec<Section>,
) {
    let top = rects.len() - 1;
    let [x0, x1, _, y1] = rects[top];
    let lo = rects[top.saturating_sub(1)];
    let w = x1 - x0;
    let theta = p.bodies[top].cap.map_or(0.0, |c| c.theta);
    let press = press_of(p);
    let ratio = match fr.law {
        Law::Coulomb(mu) if fr.drag < 1.0 || mu.atan() + theta >= 80f64.to_radians() => {
            fr.drag.min(0.8) * mu
        }
        Law::Coulomb(mu) => fr.drag * (mu.atan() + theta).tan(),
        Law::Tresca(s) if fr.drag < 1.0 => {
            let overlap = (x1.min(lo[1]) - x0.max(lo[0])).max(0.0);
            fr.drag * s * overlap / w
        }
        Law::Tresca(s) => {
            let arc = if theta > 0.0 {
                theta / theta.sin()
            } else {
                1.0
            };
            let big_s = s * (lo[1] - lo[0]).max(w * arc) / w;
            fr.drag * ((1.0 + big_s) * theta.tan() + big_s)
        }
    };
    let drag = (ratio * press).min(1e300);
    for (name, t) in [("press", [0.0, -press]), ("drag", [fr.sign * drag, 0.0])] {
        out.push(Section {
            header: "[[neumann]]",
            entries: vec![
                // Without its name the steps name an unknown load: refused, naming `loads`.
                Entry::new("name", format!("\"{name}\"")).optional(),
                Entry::new("body", format!("\"{}\"", names[top])),
                Entry::new("region", arr(&[x0, x1, y1, y1])).array().num(),
                Entry::new("traction", arr(&t)).array().num(),
            ],
        });
    }
    let mut steps = vec!["{ press = 1.0, drag = 0.0 }", "{ press = 1.0, drag = 1.0 }"];
    if fr.push_back {
        steps.push("{ press = 1.0, drag = -1.0 }");
    }
    for (loads, increments) in steps.into_iter().zip(fr.increments) {
        // `loads` defaults to no factor (docs/scene.md): removing it leaves a valid scene.
        let mut e = vec![Entry::new("loads", loads.to_string()).optional().num()];
        if increments > 1 {
            e.push(Entry::new("increments", increments.to_string()).optional());
        }
        out.push(Section {
            header: "[[step]]",
            entries: e,
        });
    }
}

/// The bodies' rectangles `[x0, x1, y0, y1]`, stacked bottom to top.
fn rects(p: &SceneParams) -> Vec<[f64; 4]> {
    let mut rects: Vec<[f64; 4]> = Vec::new();
    let mut y = 0.0;
    let mut x_prev = 0.0;
    let mut h_prev = 0.0;
    for b in &p.bodies {
        let w = b.width * b.unit;
        let mut h = if b.sliver {
            w * 1e-5
        } else {
            b.height * b.unit
        };
        // A cap stands on its arc: its block part above the arc's ends keeps the drawn height.
        if let Some(cap) = b.cap {
            h += cap.radius_sag(w).1;
        }
        let y0 = if rects.is_empty() {
            0.0
        } else {
            y + b.gap * h_prev
        };
        let x0 = x_prev + b.shift * w;
        rects.push([x0, x0 + w, y0, y0 + h]);
        y = y0 + h;
        x_prev = x0;
        h_prev = h;
    }
    rects
}

/// The cells per side of a Gmsh body's grid: about `h` wide, at least one, at most 40 (so that
/// a body stays within the harness's element limit, as [`Hmax`]'s extreme values would not).
fn cells(length: f64, h: f64) -> usize {
    let n = (length / h).ceil();
    // NaN (h = 0 over a zero length) and n < 1 (h ≤ 0 or h > length) give one cell.
    if n >= 1.0 {
        n.min(40.0) as usize
    } else {
        1
    }
}

/// The element size asked for body `b` in rectangle `r`.
fn body_hmax(b: &BodyParams, r: [f64; 4]) -> f64 {
    let [x0, x1, y0, y1] = r;
    let small = (x1 - x0).min(y1 - y0);
    match b.hmax {
        Hmax::Relative(k) => k * small.max((x1 - x0) * 0.02),
        Hmax::Absolute(v) => v,
    }
}

/// The Gmsh files of the bodies meshed by Gmsh, named as their `mesh` keys say.
fn mesh_files(p: &SceneParams) -> Vec<(String, String)> {
    p.bodies
        .iter()
        .zip(rects(p))
        .enumerate()
        .filter_map(|(i, (b, r))| {
            let clockwise = b.gmsh?;
            let h = body_hmax(b, r);
            let (nx, ny) = (cells(r[1] - r[0], h), cells(r[3] - r[2], h));
            Some((
                format!("b{i}.msh"),
                super::msh::grid(r, [nx, ny], b.q1, clockwise),
            ))
        })
        .collect()
}

/// Builds the sections of a scene: bodies stacked bottom to top, the bottom one clamped, the top
/// one loaded on its top edge, consecutive bodies in contact.
fn sections(p: &SceneParams) -> Vec<Section> {
    let mut out = vec![Section {
        header: "",
        entries: vec![Entry::new("title", "\"fuzz\"".into()).optional()],
    }];
    model_section(p, &mut out);
    let rects = rects(p);
    let names: Vec<String> = (0..p.bodies.len()).map(|i| format!("b{i}")).collect();
    body_sections(p, &rects, &names, &mut out);
    support_sections(p, &rects, &names, &mut out);
    load_section(p, &rects, &names, &mut out);
    contact_sections(p, &rects, &names, &mut out);
    probe_section(p, &rects, &names, &mut out);
    out
}

/// `[model]`: plane stress and thickness, gravity (absent when neither is drawn).
fn model_section(p: &SceneParams, out: &mut Vec<Section>) {
    let mut model = Vec::new();
    if let Some(t) = p.plane_stress {
        model.push(Entry::new("plane", "\"stress\"".into()).optional());
        model.push(Entry::new("thickness", f(t)).optional().num());
    }
    if let Some(g) = p.gravity {
        model.push(
            Entry::new("gravity", arr(&[0.0, g]))
                .optional()
                .array()
                .num(),
        );
    }
    if !model.is_empty() {
        out.push(Section {
            header: "[model]",
            entries: model,
        });
    }
}

/// One `[[body]]` per body (polygon or Gmsh file), with its `[[body.refine]]` box.
fn body_sections(p: &SceneParams, rects: &[[f64; 4]], names: &[String], out: &mut Vec<Section>) {
    for (i, (b, r)) in p.bodies.iter().zip(rects).enumerate() {
        let [x0, x1, y0, y1] = *r;
        let polygon = match b.cap {
            None => format!(
                "[{}, {}, {}, {}]",
                arr(&[x0, y0]),
                arr(&[x1, y0]),
                arr(&[x1, y1]),
                arr(&[x0, y1])
            ),
            Some(cap) => cap_polygon(cap, *r),
        };
        let h = body_hmax(b, *r);
        let mut e = vec![Entry::new("name", format!("\"{}\"", names[i]))];
        if b.gmsh.is_some() {
            // The file fixes the elements: no hmax, element or refine (docs/scene.md).
            e.push(Entry::new("mesh", format!("\"b{i}.msh\"")));
        } else {
            e.push(Entry::new("polygon", polygon).num());
            e.push(Entry::new("hmax", f(h)).num());
        }
        e.push(Entry::new("young", f(b.young)).num());
        e.push(Entry::new("poisson", f(b.poisson)).num());
        if b.q1 && b.gmsh.is_none() {
            e.push(Entry::new("element", "\"q1\"".into()).optional());
        }
        if p.gravity.is_some() {
            e.push(Entry::new("density", f(1.0)).num());
        }
        out.push(Section {
            header: "[[body]]",
            entries: e,
        });
        // A graded mesh (P1 or Q1 alike): the bottom tenth, which is the contact side of every
        // body but the lowest, finer by `k` (docs/scene.md: the box meets the body, its hmax is
        // below the body's).
        if let Some(k) = b.refine.filter(|_| b.gmsh.is_none()) {
            out.push(Section {
                header: "[[body.refine]]",
                entries: vec![
                    Entry::new("region", arr(&[x0, x1, y0, y0 + 0.1 * (y1 - y0)]))
                        .array()
                        .num(),
                    Entry::new("hmax", f(k * h)).num(),
                ],
            });
        }
    }
}

/// A cap's outline in rectangle `r`: the arc from its left end through its lowest point
/// (x0 + w/2, y0) to its right end, `chords` chords, then the top corners (counter-clockwise).
fn cap_polygon(cap: Cap, r: [f64; 4]) -> String {
    let [x0, x1, y0, y1] = r;
    let w = x1 - x0;
    let (radius, _) = cap.radius_sag(w);
    let xm = 0.5 * (x0 + x1);
    let mut points: Vec<String> = (0..=cap.chords)
        .map(|k| {
            let a = -cap.theta + 2.0 * cap.theta * k as f64 / cap.chords as f64;
            let x = if k == 0 {
                x0
            } else if k == cap.chords {
                x1
            } else {
                xm + radius * a.sin()
            };
            let y = if k == 0 || k == cap.chords {
                y0 + cap.radius_sag(w).1
            } else {
                y0 + radius * (1.0 - a.cos())
            };
            arr(&[x, y])
        })
        .collect();
    points.push(arr(&[x1, y1]));
    points.push(arr(&[x0, y1]));
    format!("[{}]", points.join(", "))
}

/// `[[dirichlet]]`: the bottom body clamped, the others by their `support`.
fn support_sections(p: &SceneParams, rects: &[[f64; 4]], names: &[String], out: &mut Vec<Section>) {
    for (i, (b, r)) in p.bodies.iter().zip(rects).enumerate() {
        let [x0, x1, y0, y1] = *r;
        let name = format!("\"{}\"", names[i]);
        // Bottom body: clamped bottom edge.  Others: by `support`, nothing (held by contact),
        // the left edge clamped, a roller on the left edge, or the left edge moved by `values`.
        let (region, value, components) = if i == 0 {
            ([x0, x1, y0, y0], p.values, None)
        } else {
            match b.support {
                0 => continue,
                1 => ([x0, x0, y0, y1], [0.0, 0.0], None),
                2 => ([x0, x0, y0, y1], [0.0, 0.0], Some("[\"x\"]")),
                _ => ([x0, x0, y0, y1], p.values, None),
            }
        };
        let mut e = vec![
            Entry::new("body", name),
            Entry::new("region", arr(&region)).array().num(),
        ];
        if value != [0.0, 0.0] {
            e.push(Entry::new("value", arr(&value)).optional().array().num());
        }
        if let Some(c) = components {
            e.push(Entry::new("components", c.into()).optional());
        }
        out.push(Section {
            header: "[[dirichlet]]",
            entries: e,
        });
    }
}

/// `[[neumann]]`: the top body's top edge, a constant or a linear traction.
fn load_section(p: &SceneParams, rects: &[[f64; 4]], names: &[String], out: &mut Vec<Section>) {
    if let Some(fr) = &p.friction {
        return friction_loads(p, fr, rects, names, out);
    }
    let top = rects.len() - 1;
    let [x0, x1, y0, y1] = rects[top];
    let mut e = vec![
        Entry::new("body", format!("\"{}\"", names[top])),
        Entry::new("region", arr(&[x0, x1, y1, y1])).array().num(),
    ];
    match p.linear {
        None => e.push(Entry::new("traction", arr(&p.load)).array().num()),
        Some(t2) => {
            let xm = 0.5 * (x0 + x1);
            let ym = 0.5 * (y0 + y1);
            e.push(
                Entry::new(
                    "points",
                    format!(
                        "[{}, {}, {}]",
                        arr(&[x0, y1]),
                        arr(&[x1, y1]),
                        arr(&[xm, ym])
                    ),
                )
                .array()
                .num(),
            );
            e.push(
                // Whether `tx` alone (or `ty` alone) is enough is not fixed by the contract, so
                // removing one of them is not counted as breaking the scene.
                Entry::new("tx", arr(&[p.load[0], t2[0], 0.0]))
                    .optional()
                    .array()
                    .num(),
            );
            e.push(
                Entry::new("ty", arr(&[p.load[1], t2[1], p.load[1]]))
                    .optional()
                    .array()
                    .num(),
            );
        }
    }
    out.push(Section {
        header: "[[neumann]]",
        entries: e,
    });
}

/// `[[contact]]` between consecutive bodies.
fn contact_sections(p: &SceneParams, rects: &[[f64; 4]], names: &[String], out: &mut Vec<Section>) {
    for i in 1..rects.len() {
        let (lo, hi) = (rects[i - 1], rects[i]);
        let mut e = vec![Entry::new(
            "bodies",
            format!("[\"{}\", \"{}\"]", names[i - 1], names[i]),
        )
        .array()];
        if p.contact_region {
            let y = hi[2];
            let d = 0.01 * (hi[3] - hi[2]).min(lo[3] - lo[2]);
            // A cap's arc rises by its sag from its lowest point: the box covers the whole arc.
            let sag = p.bodies[i]
                .cap
                .map_or(0.0, |c| c.radius_sag(hi[1] - hi[0]).1);
            let region = [lo[0].max(hi[0]), lo[1].min(hi[1]), y - d, y + sag + d];
            e.push(Entry::new("region", arr(&region)).optional().array().num());
        }
        if let Some(upper) = p.slave {
            let s = if upper { &names[i] } else { &names[i - 1] };
            e.push(Entry::new("slave", format!("\"{s}\"")).optional());
        }
        if p.mortar {
            e.push(Entry::new("formulation", "\"mortar\"".to_string()).optional());
        }
        match p.friction.as_ref().map(|fr| fr.law) {
            Some(Law::Coulomb(mu)) => e.push(Entry::new("friction", f(mu)).optional().num()),
            Some(Law::Tresca(ratio)) => e.push(
                Entry::new("tresca", f(ratio * press_of(p)))
                    .optional()
                    .num(),
            ),
            None => {}
        }
        out.push(Section {
            header: "[[contact]]",
            entries: e,
        });
    }
}

/// `[[probe]]` at the top body's centre, when drawn.
fn probe_section(p: &SceneParams, rects: &[[f64; 4]], names: &[String], out: &mut Vec<Section>) {
    if p.probe {
        let top = rects.len() - 1;
        let [x0, x1, y0, y1] = rects[top];
        out.push(Section {
            header: "[[probe]]",
            entries: vec![
                Entry::new("name", "\"centre\"".into()),
                Entry::new("body", format!("\"{}\"", names[top])),
                Entry::new("point", arr(&[0.5 * (x0 + x1), 0.5 * (y0 + y1)]))
                    .array()
                    .num(),
            ],
        });
    }
}

/// Renders sections as TOML.
pub fn render(sections: &[Section]) -> String {
    let mut s = String::new();
    for sec in sections {
        if !sec.header.is_empty() {
            s.push('\n');
            s.push_str(sec.header);
            s.push('\n');
        }
        for e in &sec.entries {
            s.push_str(e.key);
            s.push_str(" = ");
            s.push_str(&e.value);
            s.push('\n');
        }
    }
    s
}

/// The `(section, entry)` positions of entries that satisfy `keep`.
fn positions(sections: &[Section], keep: impl Fn(&Entry) -> bool) -> Vec<(usize, usize)> {
    sections
        .iter()
        .enumerate()
        .flat_map(|(s, sec)| {
            sec.entries
                .iter()
                .enumerate()
                .filter(|(_, e)| keep(e))
                .map(move |(i, _)| (s, i))
        })
        .collect()
}

/// Replaces the first number of a TOML value with `nan`.
fn poison(value: &str) -> String {
    let bytes = value.as_bytes();
    let start = (0..bytes.len()).find(|&i| {
        let c = bytes[i] as char;
        (c.is_ascii_digit() || c == '-')
            && (i == 0 || matches!(bytes[i - 1] as char, '[' | ' ' | ','))
    });
    match start {
        Some(i) => {
            let end = (i..bytes.len())
                .find(|&j| matches!(bytes[j] as char, ',' | ']'))
                .unwrap_or(bytes.len());
            format!("{}nan{}", &value[..i], &value[end..])
        }
        None => "nan".into(),
    }
}

/// One element more or fewer in the first innermost array of a TOML value.
fn relength(value: &str, longer: bool) -> String {
    let Some(close) = value.find(']') else {
        return value.to_string();
    };
    let open = value[..close].rfind('[').unwrap_or(0);
    let inner = &value[open + 1..close];
    if longer {
        let extra = if inner.trim_start().starts_with('"') {
            ", \"b0\""
        } else {
            ", 0.5"
        };
        format!("{}{}{}", &value[..close], extra, &value[close..])
    } else {
        match inner.rfind(',') {
            Some(c) => format!("{}{}", &value[..open + 1 + c], &value[close..]),
            None => format!("{}{}", &value[..open + 1], &value[close..]),
        }
    }
}

/// Applies a mutation; returns what makes the scene broken (the key backticked first, see
/// [`Broken::from_why`]) when it must be refused.
fn mutate(sections: &mut [Section], m: &Mutation) -> Option<String> {
    match m {
        Mutation::None => None,
        Mutation::RemoveKey(ix) => {
            let pos = positions(sections, |_| true);
            let (s, i) = pos[ix.index(pos.len())];
            let e = sections[s].entries.remove(i);
            e.required
                .then(|| format!("missing required key `{}` in {}", e.key, sections[s].header))
        }
        Mutation::UnknownKey(ix) => {
            let s = ix.index(sections.len());
            sections[s]
                .entries
                .push(Entry::new("colour", "\"red\"".into()));
            Some(format!("unknown key `colour` in {:?}", sections[s].header))
        }
        Mutation::WrongLength(ix, longer) => {
            let pos = positions(sections, |e| e.fixed_array);
            if pos.is_empty() {
                return None;
            }
            let (s, i) = pos[ix.index(pos.len())];
            let e = &mut sections[s].entries[i];
            e.value = relength(&e.value, *longer);
            Some(format!(
                "array `{}` one {} ({})",
                e.key,
                if *longer { "longer" } else { "shorter" },
                sections[s].header
            ))
        }
        Mutation::Nan(ix) => {
            let pos = positions(sections, |e| e.numeric);
            let (s, i) = pos[ix.index(pos.len())];
            let e = &mut sections[s].entries[i];
            e.value = poison(&e.value);
            Some(format!("nan in `{}` ({})", e.key, sections[s].header))
        }
        Mutation::UnknownBody(ix) => {
            let pos = positions(sections, |e| matches!(e.key, "body" | "bodies" | "slave"));
            if pos.is_empty() {
                return None;
            }
            let (s, i) = pos[ix.index(pos.len())];
            let e = &mut sections[s].entries[i];
            e.value = e.value.replacen("\"b", "\"nobody", 1);
            Some(format!(
                "unknown body name in `{}` ({})",
                e.key, sections[s].header
            ))
        }
        Mutation::ControlChar(ix, c) => {
            let names = positions(sections, |e| e.key == "name" && e.value.starts_with("\"b"));
            if names.is_empty() {
                return None;
            }
            let (s, i) = names[ix.index(names.len())];
            let old = sections[s].entries[i].value.clone();
            let bare = old.trim_matches('"');
            let escaped = format!("\"{}\\u{:04X}{}\"", bare, *c as u32, "x");
            // Rename every reference, so the scene stays consistent.
            for sec in sections.iter_mut() {
                for e in &mut sec.entries {
                    if matches!(e.key, "name" | "body" | "bodies" | "slave") {
                        e.value = e.value.replace(&old, &escaped);
                    }
                }
            }
            None
        }
    }
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        12 => Just(Mutation::None),
        1 => any::<Index>().prop_map(Mutation::RemoveKey),
        1 => any::<Index>().prop_map(Mutation::UnknownKey),
        2 => (any::<Index>(), any::<bool>()).prop_map(|(i, l)| Mutation::WrongLength(i, l)),
        1 => any::<Index>().prop_map(Mutation::Nan),
        1 => any::<Index>().prop_map(Mutation::UnknownBody),
        1 => (any::<Index>(), select(vec!['\u{1}', '\u{8}', '\u{1b}', '\u{7f}', '\u{c}']))
            .prop_map(|(i, c)| Mutation::ControlChar(i, c)),
    ]
}

/// The backends of this build, with the weight each is drawn with: `auto`, the default, as
/// often as four named ones; every other name the command line accepts (each algorithm in its
/// own form, clarabel and osqp on the condensed dual too) once.
pub fn backends() -> Vec<(u32, BackendKind)> {
    std::iter::once((4, BackendKind::Auto))
        .chain(
            BackendKind::ALL
                .into_iter()
                .chain([BackendKind::ClarabelDual, BackendKind::OsqpDual])
                .map(|k| (1, k)),
        )
        .filter(|(_, k)| k.available())
        .collect()
}

/// A backend drawn with the weights of [`backends`].
fn backend() -> impl Strategy<Value = BackendKind> {
    let weighted: Vec<_> = backends()
        .into_iter()
        .map(|(w, k)| (w, Just(k).boxed()))
        .collect();
    proptest::strategy::Union::new_weighted(weighted)
}

/// A whole test case: scene text, whether it must be refused, and a backend.  One case in four
/// is frictional ([`frictional_scene_params`]); the other three are drawn exactly as before
/// friction was added.
pub fn case() -> impl Strategy<Value = Case> {
    prop_oneof![
        3 => case_of(scene_params().boxed()),
        1 => case_of(frictional_scene_params().boxed()),
    ]
}

/// A case of the scenes `scenes` draws.
fn case_of(scenes: BoxedStrategy<SceneParams>) -> impl Strategy<Value = Case> {
    (scenes, mutation(), backend(), prop::bool::weighted(0.1)).prop_map(
        |(mut p, m, backend, unload)| {
            // One scene in ten has nothing loaded or prescribed (its answer is known: u = 0); a
            // frictional one is always pressed.
            if unload && p.friction.is_none() {
                p.load = [0.0, 0.0];
                p.linear = None;
                p.gravity = None;
                p.values = [0.0, 0.0];
            }
            let mut secs = sections(&p);
            let clean = render(&secs);
            let must_refuse = mutate(&mut secs, &m).map(|why| Broken {
                clean: Some(clean),
                ..Broken::from_why(&why)
            });
            // Bodies are stacked upwards, so a gap ≥ 0 to the one below means no overlap at all.
            let unloaded = p.load == [0.0, 0.0]
                && p.linear.is_none_or(|t| t == [0.0, 0.0])
                && p.gravity.is_none()
                && p.values == [0.0, 0.0];
            let apart = p.bodies.iter().skip(1).all(|b| b.gap >= 0.0);
            let at_rest = unloaded && apart && p.friction.is_none() && matches!(m, Mutation::None);
            Case {
                toml: render(&secs),
                files: mesh_files(&p),
                must_refuse,
                backend,
                at_rest,
            }
        },
    )
}
