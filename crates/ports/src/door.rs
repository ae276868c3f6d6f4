//! The communication phase's reads and writes of the CPU's devices, through
//! the Cpu door (ARCHITECTURE.md "One door to device memory").

use softplc_core::access::RBlock;
use softplc_core::device::DeviceKind;
use softplc_core::engine::Cpu;

pub fn bit(cpu: &Cpu, kind: DeviceKind, n: u32) -> bool {
    cpu.memory().get_bit(kind, n as i64).unwrap_or(false)
}

pub fn word(cpu: &Cpu, kind: DeviceKind, n: u32) -> u16 {
    cpu.memory().get_word(kind, n as i64).unwrap_or(0)
}

pub fn set_bit(cpu: &mut Cpu, kind: DeviceKind, n: u32, v: bool) {
    if let Ok(s) = cpu.span(kind, n, 1, RBlock::First) {
        let _ = cpu.write_span_bits(&s, &[v]);
    }
}

pub fn set_words(cpu: &mut Cpu, kind: DeviceKind, n: u32, v: &[u16]) {
    if v.is_empty() {
        return;
    }
    if let Ok(s) = cpu.span(kind, n, v.len() as u32, RBlock::First) {
        let _ = cpu.write_span_words(&s, v);
    }
}

pub fn set_word(cpu: &mut Cpu, kind: DeviceKind, n: u32, v: u16) {
    set_words(cpu, kind, n, &[v]);
}
