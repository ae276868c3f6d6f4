//! Differential test of S.PIDCONT/PIDCONT against an independent model of the
//! seed-001 formulas (001 §3.1.2, §3.2.2) and of softplc's documented
//! decisions (notes `shared/spec/pid-instructions.md` §1.3–§1.8, §2.5, §2.6;
//! the state grids of the work-area encoding: PVf on a 2⁻¹⁶ grid, MV on a 2⁻³⁶
//! grid, both rounded half away from zero).
//!
//! The model below is written from the specification only: it keeps EVn−1 as
//! a number (the implementation recomputes it from PVfn−1 and SVn−1), keeps its
//! state in plain Rust structs (the implementation only in device words), and
//! schedules loops with its own bookkeeping. Thousands of random parameter
//! sets, scan-time sequences and PV/SV/mode sequences are run through both, and
//! every SV, MV, PVf, MV_MAN and ALARM word must match after every scan.

mod common;
use common::Plc;
use proptest::prelude::*;
use softplc_core::device::DeviceKind;
use softplc_core::engine::CpuState;

// ------------------------------------------------------------ the model

#[derive(Clone, Copy, Debug)]
struct Params {
    reverse: bool,
    ts: i32,
    kp: i32,
    ti: i32,
    td: i32,
    alpha: i32,
    mvll: i32,
    mvhl: i32,
    dmvl: i32,
    dpvl: i32,
    kd: i32,
}

/// The user-visible words of one loop.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Words {
    sv: i16,
    pv: i16,
    mv: i16,
    pvf: i16,
    mvman: i16,
    mode: i16,
    alarm: u16,
}

#[derive(Clone, Copy, Debug, Default)]
struct ModelLoop {
    started: bool,
    was_auto: bool,
    left_over: bool,
    acc_ms: u32,
    mv: f64,
    pvf_1: f64,
    pvf_2: f64,
    ev_1: f64,
    d_1: f64,
    pv_1: i32,
}

struct Model {
    incomplete: bool,
    k: usize,
    split_first: bool,
    params: Vec<Params>,
    loops: Vec<ModelLoop>,
    rest_us: u64,
}

fn grid(x: f64, bits: i32) -> f64 {
    let s = 2f64.powi(bits);
    (x * s).round() / s
}

fn shown(x: f64) -> i16 {
    let r = x.round();
    if r > 32767.0 {
        32767
    } else if r < -32768.0 {
        -32768
    } else {
        r as i16
    }
}

fn lim(limited: bool, v: i16, lo: i32, hi: i32) -> i32 {
    let v = v as i32;
    if limited {
        v.max(lo).min(hi)
    } else {
        v
    }
}

impl Model {
    /// One PIDCONT execution. `scan_us`: scan time measured at the previous
    /// END; `copy_pv` = SM794/SM774 OFF; `free` = SD range bits (1 = unlimited).
    #[allow(clippy::needless_range_loop)] // `i` indexes w, loops and params
    fn exec(&mut self, w: &mut [Words], scan_us: u64, copy_pv: bool, free: u32) {
        let total = self.rest_us + scan_us;
        self.rest_us = total % 1000;
        let add = (total / 1000).min(65535) as u32;
        let n = self.loops.len();
        let mut first_now = vec![];
        let mut due: Vec<(bool, usize)> = vec![];
        for i in 0..n {
            let auto = w[i].mode == 1;
            let limited = free >> i & 1 == 0;
            let l = &mut self.loops[i];
            if !l.started {
                if self.split_first {
                    due.push((l.left_over, i));
                } else {
                    first_now.push(i);
                }
                continue;
            }
            l.acc_ms = (l.acc_ms + add).min(65535);
            if auto && !l.was_auto {
                let m = lim(limited, w[i].mvman, -50, 2050);
                w[i].mv = m as i16;
                l.mv = m as f64;
            } else if !auto && l.was_auto {
                w[i].mvman = w[i].mv;
            }
            l.was_auto = auto;
            if l.acc_ms >= self.params[i].ts as u32 * 10 {
                due.push((l.left_over, i));
            } else {
                l.left_over = false;
            }
        }
        for i in first_now {
            self.first(i, w, copy_pv, free);
        }
        // Left-over loops first, then by loop number; at most k.
        due.sort_by_key(|&(left, i)| (!left, i));
        for (slot, &(_, i)) in due.iter().enumerate() {
            if slot >= self.k {
                self.loops[i].left_over = true;
                continue;
            }
            self.loops[i].left_over = false;
            if self.loops[i].started {
                let ts = self.loops[i].acc_ms / 10;
                self.loops[i].acc_ms -= ts * 10;
                self.sample(i, w, ts as i32, false, copy_pv, free);
            } else {
                self.first(i, w, copy_pv, free);
            }
        }
    }

    fn first(&mut self, i: usize, w: &mut [Words], copy_pv: bool, free: u32) {
        let limited = free >> i & 1 == 0;
        let pv = lim(limited, w[i].pv, -50, 2050);
        self.loops[i] = ModelLoop {
            started: true,
            was_auto: w[i].mode == 1,
            left_over: false,
            acc_ms: 0,
            mv: w[i].mv as f64,
            pvf_1: pv as f64,
            pvf_2: pv as f64,
            ev_1: 0.0,
            d_1: 0.0,
            pv_1: pv,
        };
        let ts = self.params[i].ts;
        self.sample(i, w, ts, true, copy_pv, free);
    }

    fn sample(
        &mut self,
        i: usize,
        w: &mut [Words],
        ts: i32,
        first: bool,
        copy_pv: bool,
        free: u32,
    ) {
        let p = self.params[i];
        let limited = free >> i & 1 == 0;
        let incomplete = self.incomplete;
        let l = &mut self.loops[i];
        let sv = lim(limited, w[i].sv, 0, 2000);
        let pv = lim(limited, w[i].pv, -50, 2050);
        if !first && (pv - l.pv_1).abs() > lim(limited, p.dpvl as i16, 0, 2000) {
            w[i].alarm |= 1;
        }
        let a = p.alpha as f64 / 100.0;
        let pvf = grid(pv as f64 + a * (l.pvf_1 - pv as f64), 16);
        w[i].pvf = shown(pvf);
        let err = |sv: i32| {
            if p.reverse {
                sv as f64 - pvf
            } else {
                pvf - sv as f64
            }
        };
        if w[i].mode == 0 {
            let sv_next = if copy_pv {
                w[i].sv = pv as i16;
                lim(limited, pv as i16, 0, 2000)
            } else {
                sv
            };
            l.ev_1 = err(sv_next);
            l.pvf_2 = l.pvf_1;
            l.pvf_1 = pvf;
            l.d_1 = 0.0;
            l.pv_1 = pv;
            return;
        }
        let ev = err(sv);
        let mut second = (pvf - 2.0 * l.pvf_1) + l.pvf_2;
        if p.reverse {
            second = -second;
        }
        let (td, tsf) = (p.td as f64, ts as f64);
        let d = if p.td == 0 {
            0.0
        } else if !incomplete || p.kd > 30000 {
            td / tsf * second
        } else if p.kd == 0 {
            0.0
        } else {
            let kd = p.kd as f64;
            let den = tsf * kd + 100.0 * td;
            td * kd / den * second + 100.0 * td / den * l.d_1
        };
        let i_term = if p.ti > 30000 {
            0.0
        } else {
            tsf / (10.0 * p.ti as f64) * ev
        };
        let dmv = p.kp as f64 / 100.0 * ((ev - l.ev_1) + i_term + d);
        if dmv.abs() > lim(limited, p.dmvl as i16, 0, 2000) as f64 {
            w[i].alarm |= 2;
        }
        let hi = lim(limited, p.mvhl as i16, -50, 2050) as f64;
        let lo = lim(limited, p.mvll as i16, -50, 2050) as f64;
        let mv = grid((l.mv + dmv).min(hi).max(lo), 36);
        l.mv = mv;
        w[i].mv = shown(mv);
        l.ev_1 = ev;
        l.pvf_2 = l.pvf_1;
        l.pvf_1 = pvf;
        l.d_1 = if incomplete { d } else { 0.0 };
        l.pv_1 = pv;
    }
}

// ------------------------------------------------------------ random cases

/// One scan's inputs.
#[derive(Clone, Debug)]
struct Step {
    scan_us: u64,
    pv: Vec<i16>,
    /// New SV for each loop, if the "user" writes one this scan.
    sv: Vec<Option<i16>>,
    /// MAN/AUTO written this scan.
    mode: Vec<Option<bool>>,
    mvman: Vec<Option<i16>>,
    clear_alarm: bool,
    sm_on: bool,
}

#[derive(Clone, Debug)]
struct Case {
    incomplete: bool,
    k: usize,
    split_first: bool,
    params: Vec<Params>,
    sv0: Vec<i16>,
    mv0: Vec<i16>,
    auto0: Vec<bool>,
    free: u32,
    steps: Vec<Step>,
}

fn word() -> impl Strategy<Value = i16> {
    prop_oneof![
        6 => -100i16..2200,
        1 => any::<i16>(),
        1 => Just(0i16),
    ]
}

fn params(incomplete: bool) -> impl Strategy<Value = Params> {
    (
        any::<bool>(),
        prop_oneof![3 => 1i32..60, 1 => 1i32..=6000],
        prop_oneof![3 => 1i32..500, 1 => 1i32..=10000],
        prop_oneof![3 => 1i32..3000, 1 => 1i32..=32767],
        prop_oneof![2 => Just(0i32), 2 => 0i32..3000, 1 => 0i32..=30000],
        prop_oneof![2 => Just(0i32), 3 => 0i32..=100],
        (word(), word()),
        (word(), word()),
        prop_oneof![
            1 => Just(0i32),
            1 => Just(32767i32),
            3 => 1i32..2000,
            1 => 0i32..=32767
        ],
    )
        .prop_map(
            move |(reverse, ts, kp, ti, td, alpha, (a, b), (dmvl, dpvl), kd)| Params {
                reverse,
                ts,
                kp,
                ti,
                td,
                alpha,
                mvll: a.min(b) as i32,
                mvhl: a.max(b) as i32,
                dmvl: dmvl as i32,
                dpvl: dpvl as i32,
                kd: if incomplete { kd } else { 0 },
            },
        )
}

fn case() -> impl Strategy<Value = Case> {
    (any::<bool>(), 1usize..=3, any::<bool>(), 8usize..32)
        .prop_flat_map(|(incomplete, n, split_first, len)| {
            let step = (
                prop_oneof![
                    3 => Just(10_000u64),
                    3 => 1_000u64..80_000,
                    1 => 100u64..3_000,
                    1 => 80_000u64..700_000,
                ],
                prop::collection::vec(word(), n),
                prop::collection::vec(prop::option::weighted(0.1, word()), n),
                prop::collection::vec(prop::option::weighted(0.08, any::<bool>()), n),
                prop::collection::vec(prop::option::weighted(0.1, word()), n),
                prop::bool::weighted(0.1),
                prop::bool::weighted(0.2),
            )
                .prop_map(|(scan_us, pv, sv, mode, mvman, clear_alarm, sm_on)| Step {
                    scan_us,
                    pv,
                    sv,
                    mode,
                    mvman,
                    clear_alarm,
                    sm_on,
                });
            (
                Just(incomplete),
                1usize..=n,
                Just(split_first),
                prop::collection::vec(params(incomplete), n),
                prop::collection::vec(word(), n),
                prop::collection::vec(word(), n),
                prop::collection::vec(prop::bool::weighted(0.8), n),
                0u32..8,
                prop::collection::vec(step, len),
            )
        })
        .prop_map(
            |(incomplete, k, split_first, params, sv0, mv0, auto0, free, steps)| Case {
                incomplete,
                k,
                split_first,
                params,
                sv0,
                mv0,
                auto0,
                free,
                steps,
            },
        )
}

// ------------------------------------------------------------ running both

const DATA: u32 = 500;
const IO: u32 = 1000;

fn put(p: &mut Plc, kind: DeviceKind, n: u32, v: i64) {
    p.cpu.set_word(kind, n as i64, v as u16).unwrap();
}

fn peek(p: &Plc, n: u32) -> i16 {
    p.cpu.memory().get_word(DeviceKind::D, n as i64).unwrap() as i16
}

fn run_case(c: &Case) -> Result<(), TestCaseError> {
    let (init, cont, per_data, per_io, sm, sd) = if c.incomplete {
        ("SP.PIDINIT", "S.PIDCONT", 14, 23, 794, 794)
    } else {
        ("PIDINITP", "PIDCONT", 10, 18, 774, 774)
    };
    let n = c.params.len();
    let mut p = Plc::new(&format!("LD SM400\n{init} D{DATA}\n{cont} D{IO}\nEND\n"));
    put(&mut p, DeviceKind::D, DATA, n as i64);
    put(&mut p, DeviceKind::D, DATA + 1, c.k as i64);
    for (i, q) in c.params.iter().enumerate() {
        let mut w = vec![
            q.reverse as i32,
            q.ts,
            q.kp,
            q.ti,
            q.td,
            q.alpha,
            q.mvll,
            q.mvhl,
            q.dmvl,
            q.dpvl,
        ];
        if c.incomplete {
            w.extend([0, q.kd, 0, 0]);
        }
        for (j, v) in w.iter().enumerate() {
            put(
                &mut p,
                DeviceKind::D,
                DATA + 2 + (per_data * i + j) as u32,
                *v as i64,
            );
        }
    }
    put(&mut p, DeviceKind::D, IO, c.split_first as i64);
    put(&mut p, DeviceKind::SD, sd, c.free as i64);
    let mut words: Vec<Words> = (0..n)
        .map(|i| Words {
            sv: c.sv0[i],
            mv: c.mv0[i],
            mode: c.auto0[i] as i16,
            ..Words::default()
        })
        .collect();
    let base = |i: usize| IO + 10 + (per_io * i) as u32;
    let mut model = Model {
        incomplete: c.incomplete,
        k: c.k,
        split_first: c.split_first,
        params: c.params.clone(),
        loops: vec![ModelLoop::default(); n],
        rest_us: 0,
    };
    let mut prev_scan_us = 0u64;
    for (s, step) in c.steps.iter().enumerate() {
        for (i, w) in words.iter_mut().enumerate() {
            w.pv = step.pv[i];
            if let Some(v) = step.sv[i] {
                w.sv = v;
            }
            if let Some(a) = step.mode[i] {
                w.mode = a as i16;
            }
            if let Some(v) = step.mvman[i] {
                w.mvman = v;
            }
            if step.clear_alarm {
                w.alarm = 0;
            }
            let b = base(i);
            for (off, v) in [
                (0, w.sv as i64),
                (1, w.pv as i64),
                (2, w.mv as i64),
                (4, w.mvman as i64),
                (5, w.mode as i64),
                (6, w.alarm as i64),
            ] {
                put(&mut p, DeviceKind::D, b + off, v);
            }
        }
        p.cpu.set_bit(DeviceKind::SM, sm, step.sm_on).unwrap();
        p.scan_time_us(step.scan_us).scan();
        prop_assert_eq!(p.state(), CpuState::Run, "error {:?}", p.error());
        model.exec(&mut words, prev_scan_us, !step.sm_on, c.free);
        prev_scan_us = step.scan_us;
        for (i, w) in words.iter().enumerate() {
            let b = base(i);
            let got = Words {
                sv: peek(&p, b),
                pv: peek(&p, b + 1),
                mv: peek(&p, b + 2),
                pvf: peek(&p, b + 3),
                mvman: peek(&p, b + 4),
                mode: peek(&p, b + 5),
                alarm: peek(&p, b + 6) as u16,
            };
            prop_assert_eq!(&got, w, "scan {} loop {}", s + 1, i + 1);
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 2000,
        ..ProptestConfig::default()
    })]

    #[test]
    fn pidcont_matches_the_model(c in case()) {
        run_case(&c)?;
    }
}

/// A hand-made case: the §5.8 D vector through the model, so a broken model
/// cannot pass the differential test by agreeing with a broken implementation.
#[test]
fn model_reproduces_vector_d() {
    let p = Params {
        reverse: true,
        ts: 100,
        kp: 100,
        ti: 32767,
        td: 100,
        alpha: 0,
        mvll: 0,
        mvhl: 2000,
        dmvl: 2000,
        dpvl: 2000,
        kd: 800,
    };
    let mut m = Model {
        incomplete: true,
        k: 1,
        split_first: false,
        params: vec![p],
        loops: vec![ModelLoop::default()],
        rest_us: 0,
    };
    let mut w = [Words {
        sv: 600,
        mode: 1,
        ..Words::default()
    }];
    let mut mv = vec![];
    for (s, pv) in [500, 500, 600, 600].into_iter().enumerate() {
        w[0].pv = pv;
        m.exec(&mut w, if s == 0 { 0 } else { 1_000_000 }, true, 0);
        mv.push(w[0].mv);
    }
    assert_eq!(mv, [100, 100, 0, 79]);
}
