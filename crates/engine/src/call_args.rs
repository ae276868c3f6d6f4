//! The function devices of a subroutine called with arguments (004 §10.3.1):
//! each call level has its own FX/FY/FD. The call saves the caller's, loads
//! the arguments (argument n into FXn and FYn for a bit, FDn's 4 words for a
//! word or constant), and the return takes FYn/FDn, restores the caller's
//! and writes them back to the arguments. All on the stack: no allocation.

use softplc_ir::device::{DeviceKind, DeviceMemory};
use softplc_ir::fault::Fault;
use softplc_ir::ops::FnArg;

/// FX/FY points a call level uses (arguments S1-S5 use 0-4; the device
/// table has 16 of each, all saved).
const BITS: usize = 16;
/// FD0-FD4, 4 words each.
const WORDS: usize = 20;

/// One level's function devices.
#[derive(Clone, Copy)]
pub(crate) struct Frame {
    fx: [bool; BITS],
    fy: [bool; BITS],
    fd: [u16; WORDS],
}

impl Frame {
    const EMPTY: Frame = Frame {
        fx: [false; BITS],
        fy: [false; BITS],
        fd: [0; WORDS],
    };

    fn read(mem: &DeviceMemory) -> Frame {
        let mut f = Frame::EMPTY;
        let (x, y, d) = bases(mem);
        f.fx.copy_from_slice(&mem.bits[x..x + BITS]);
        f.fy.copy_from_slice(&mem.bits[y..y + BITS]);
        f.fd.copy_from_slice(&mem.words[d..d + WORDS]);
        f
    }

    fn write(&self, mem: &mut DeviceMemory) {
        let (x, y, d) = bases(mem);
        mem.bits[x..x + BITS].copy_from_slice(&self.fx);
        mem.bits[y..y + BITS].copy_from_slice(&self.fy);
        mem.words[d..d + WORDS].copy_from_slice(&self.fd);
    }
}

fn bases(mem: &DeviceMemory) -> (usize, usize, usize) {
    let m = &mem.map;
    (
        m.base(DeviceKind::FX) as usize,
        m.base(DeviceKind::FY) as usize,
        m.base(DeviceKind::FD) as usize,
    )
}

/// Whether the device table has the function devices a frame covers (a
/// dialect without them cannot compile arguments; never panic anyway).
fn present(mem: &DeviceMemory) -> bool {
    let m = &mem.map;
    m.points(DeviceKind::FX) as usize >= BITS
        && m.points(DeviceKind::FY) as usize >= BITS
        && m.points(DeviceKind::FD) as usize * 4 >= WORDS
}

/// At the call: reads the arguments, saves the caller's frame and loads the
/// callee's. Returns the caller's frame.
pub(crate) fn enter(mem: &mut DeviceMemory, args: &[FnArg]) -> Result<Frame, Fault> {
    if !present(mem) {
        return Err(Fault::Range);
    }
    let mut new = Frame::EMPTY;
    for (n, a) in args.iter().enumerate().take(5) {
        match a {
            FnArg::Bit { dev, .. } => {
                let v = mem.read_bit(dev)?;
                new.fx[n] = v;
                new.fy[n] = v;
            }
            FnArg::Word { dev, .. } => {
                let i = mem.block_start(dev, 4)?;
                new.fd[4 * n..4 * n + 4].copy_from_slice(&mem.words[i..i + 4]);
            }
            FnArg::Const(k) => new.fd[4 * n..4 * n + 4].copy_from_slice(k),
        }
    }
    let caller = Frame::read(mem);
    new.write(mem);
    Ok(caller)
}

/// At the return: takes the callee's FY/FD, restores the caller's frame and
/// writes the outputs back to the arguments.
pub(crate) fn leave(mem: &mut DeviceMemory, args: &[FnArg], caller: &Frame) -> Result<(), Fault> {
    let out = Frame::read(mem);
    caller.write(mem);
    for (n, a) in args.iter().enumerate().take(5) {
        match a {
            FnArg::Bit { dev, back: true } => mem.write_bit(dev, out.fy[n])?,
            FnArg::Word { dev, back: true } => {
                let i = mem.block_start(dev, 4)?;
                mem.words[i..i + 4].copy_from_slice(&out.fd[4 * n..4 * n + 4]);
            }
            _ => {}
        }
    }
    Ok(())
}
