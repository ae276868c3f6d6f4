//! Selectors and average (000 §9.13-§9.16): S.HS, S.LS, S.MID, S.AVE over
//! n = 1..16 inputs. Not in Table 14.2: every error reports SD1503 = 1.

use softplc_ir::device::DeviceMemory;
use softplc_ir::fault::Fault;
use softplc_ir::ops::Block;
use softplc_lang::isa::{Def, Doc};

use super::common::{
    area, count_word, def, dummy, result, Area, BlockMemory, InputList, PcError, Sys,
};
use crate::{Args, ExecCtx, Instr};

static SEL: Doc = Doc {
    family: "process control: selectors",
    cite: "000 §9.13 L14345-14621, §9.14 L14622-14896, §9.15 L14897-15183",
    notes: "n = 1..16 (else 4100, SD1502 = 3); BB bit of every input equal to the result; S.MID: \
            stable ascending sort, the lower middle for even n",
};
static AVE: Doc = Doc {
    family: "process control: selectors",
    cite: "000 §9.16 L15184-15326",
    notes: "(E1 + … + En)/n in f32, n = 1..16",
};

pub static DEFS: &[Def] = &[
    def("S.HS", 4, &SEL, Select::compile_hs),
    def("S.LS", 4, &SEL, Select::compile_ls),
    def("S.MID", 4, &SEL, Select::compile_mid),
    def("S.AVE", 4, &AVE, Select::compile_ave),
];

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Pick {
    High,
    Low,
    Middle,
    Average,
}

/// 000 §9.13 S.HS L14345-14621, §9.14 S.LS L14622-14896, §9.15 S.MID
/// L14897-15183, §9.16 S.AVE L15184-15326.
///
/// 000 §9.13-§9.16 `S.x S1 D1 S2(dmy) D2(dmy)`: S1 +0 n (BIN16, 1..16),
/// +1/+2 E1 … +2n−1/+2n En (1 + 2n words); D1 +0 BW, +2 BB (BB1..BB16 = b0..b15:
/// input i gave the result; not for S.AVE, whose D1 is 2 words).
/// * S.HS: BW = max, S.LS: BW = min; every input equal to it is marked
///   (L14584-14589).
/// * S.MID: the inputs sorted ascending, equal values in input order, BW =
///   the middle one, the smaller middle one for even n (L15140-15169; E =
///   2, 5, 1, 4, 3 → 3 with BB5).
/// * S.AVE: BW = (E1 + E2 + … + En)/n (L15308-15318).
#[derive(Debug)]
struct Select {
    pick: Pick,
    sys: Sys,
    s1: Block,
    d1: Block,
}

impl Select {
    fn compile_hs(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Select::compile(a, Pick::High)
    }

    fn compile_ls(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Select::compile(a, Pick::Low)
    }

    fn compile_mid(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Select::compile(a, Pick::Middle)
    }

    fn compile_ave(a: &mut Args<'_, '_>) -> Option<Box<dyn Instr>> {
        Select::compile(a, Pick::Average)
    }

    fn compile(a: &mut Args<'_, '_>, pick: Pick) -> Option<Box<dyn Instr>> {
        if !a.count(&[4]) {
            return None;
        }
        let sys = Sys::new(a)?;
        let s1 = area(a, 0, 3, "input data");
        let words = if pick == Pick::Average { 2 } else { 3 };
        let d1 = area(a, 1, words, "block memory");
        dummy(a, 2)?;
        dummy(a, 3)?;
        Some(Box::new(Select {
            pick,
            sys,
            s1: s1?,
            d1: d1?,
        }))
    }

    fn body(&self, m: &mut DeviceMemory, s1: Area, d1: Area, n: usize) -> Result<(), PcError> {
        let mut e = [0f32; 16];
        for (i, v) in e[..n].iter_mut().enumerate() {
            *v = s1.real(m, InputList::e.nth(i), 1)?;
        }
        let e = &e[..n];
        let bw = match self.pick {
            Pick::High => e.iter().copied().fold(e[0], f32::max),
            Pick::Low => e.iter().copied().fold(e[0], f32::min),
            Pick::Middle => {
                // Insertion sort of the indices: stable, no allocation.
                let mut ix = [0u8; 16];
                for i in 0..n {
                    let mut j = i;
                    while j > 0 && e[ix[j - 1] as usize] > e[i] {
                        ix[j] = ix[j - 1];
                        j -= 1;
                    }
                    ix[j] = i as u8;
                }
                e[ix[(n - 1) / 2] as usize]
            }
            Pick::Average => {
                let sum = e.iter().fold(0f32, |s, &v| s + v);
                d1.set(m, BlockMemory::bw, result(sum / n as f32, 1)?);
                return Ok(());
            }
        };
        let bb = e
            .iter()
            .enumerate()
            .fold(0u16, |bb, (i, &v)| bb | ((v == bw) as u16) << i);
        d1.set(m, BlockMemory::bw, bw);
        d1.set(m, BlockMemory::bb, bb);
        Ok(())
    }
}

impl Instr for Select {
    fn exec(&self, cx: &mut ExecCtx<'_>) -> Result<(), Fault> {
        let words = if self.pick == Pick::Average { 2 } else { 3 };
        let s1 = Area::of(cx.mem, &self.s1, 1)?;
        let d1 = Area::of(cx.mem, &self.d1, words)?;
        let n = match count_word(cx.mem, s1, InputList::n, 1, 16, 1) {
            Ok(n) => n,
            Err(e) => return Err(self.sys.fail(cx.mem, e)),
        };
        let s1 = Area::of(cx.mem, &self.s1, InputList::e.nth(n).offset() as u32)?;
        self.sys.run(cx.mem, |m| self.body(m, s1, d1, n))
    }
}
