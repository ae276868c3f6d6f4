//! What one CPU's END moves between the CPUs of a multi-CPU system, resolved
//! once when the system is built so that END copies spans and nothing else:
//! the own-operation information area (004 L9049-9111, table 16.1), the
//! auto refresh (L8735-8948), the mirrors of each CPU's shared memory and of
//! the buffer memory of modules in the others, and the out-of-group I/O
//! (L9119-9215).

use softplc_ir::access::{RBlock, Span};
use softplc_ir::device::{DeviceKind, CPU1_UNIT, REFRESH_AREA, SHARED_MEMORY_WORDS};

use crate::engine::Cpu;
use crate::project::multi_cpu::MultiCpuParams;

/// The own-operation information area: (shared address, SD number, words).
/// 0H is the valid flag; 1CH is empty (table 16.1). 1FH takes SD203, the
/// operating status, where the table names SD202 (the LED bits, whose
/// meaning 1FH's "CPU operating status" does not match).
pub const OWN_INFO: &[(u32, u32, u32)] = &[(1, 0, 27), (0x1D, 200, 2), (0x1F, 203, 1)];
/// The longest copy: one shared memory.
pub(super) const SCRATCH_WORDS: usize = SHARED_MEMORY_WORDS as usize;
/// Words of the own-operation information area mirrored to the others.
pub const OWN_INFO_WORDS: u32 = 0x20;

/// A copy of `words` words from span `from` of one CPU to span `to` of
/// another (or the same).
#[derive(Clone, Debug)]
pub(super) struct Copy {
    pub from: Span,
    pub to: Span,
    pub words: usize,
}

/// Everything CPU `i`'s END moves, in order.
#[derive(Clone, Debug)]
pub(super) struct EndPlan {
    /// SD → own shared memory (own-operation information).
    pub own_info: Vec<Copy>,
    /// The information area's valid flag (address 0H) in own shared memory.
    pub valid: Span,
    /// Own send devices → own refresh area.
    pub publish: Vec<Copy>,
    /// The CPU's shared memory and controlled modules' buffer memories,
    /// to the same window in every other CPU: (other CPU, copy).
    pub mirror: Vec<(usize, Copy)>,
    /// Out-of-group inputs and outputs to the CPUs that load them:
    /// (other CPU, first X/Y, points, is input).
    pub io: Vec<(usize, u32, u32, bool)>,
    /// Every other CPU's refresh area (in this CPU's mirror of it) → this
    /// CPU's devices.
    pub import: Vec<Copy>,
}

fn span(cpu: &Cpu, kind: DeviceKind, n: u32, len: u32) -> Result<Span, String> {
    cpu.span(kind, n, len, RBlock::First)
        .map_err(|e| format!("CPU {}: {e}", cpu_no(cpu)))
}

fn cpu_no(cpu: &Cpu) -> u32 {
    cpu.memory().map.own_cpu().unwrap_or(1)
}

/// The G number of address `addr` of CPU `of`'s (0-based) shared memory
/// in `cpu`'s memory.
fn shared(cpu: &Cpu, of: usize, addr: u32, words: u32) -> Result<Span, String> {
    let map = &cpu.memory().map;
    let g = map
        .buffer(CPU1_UNIT + of as u32, addr, words)
        .map_err(|e| {
            format!(
                "CPU {}: shared memory of CPU {}: {e:?}",
                cpu_no(cpu),
                of + 1
            )
        })?;
    span(cpu, DeviceKind::G, g, words)
}

/// The plans of every CPU. `params` are the refresh settings of each CPU
/// (the device each refreshes; their word counts are CPU 1's, the ones
/// that consistent CPUs share).
pub(super) fn plans(
    cpus: &[&Cpu],
    params: &[Option<MultiCpuParams>],
) -> Result<Vec<EndPlan>, String> {
    let n = cpus.len();
    let words_of = params
        .first()
        .and_then(|p| p.as_ref())
        .filter(|p| p.cpus as usize == n);
    let mut plans = Vec::with_capacity(n);
    for (i, cpu) in cpus.iter().enumerate() {
        let mut plan = EndPlan {
            own_info: Vec::new(),
            valid: shared(cpu, i, 0, 1)?,
            publish: Vec::new(),
            mirror: Vec::new(),
            io: Vec::new(),
            import: Vec::new(),
        };
        for &(addr, sd, words) in OWN_INFO {
            plan.own_info.push(Copy {
                from: span(cpu, DeviceKind::SD, sd, words)?,
                to: shared(cpu, i, addr, words)?,
                words: words as usize,
            });
        }
        // Each CPU's own devices, with the word counts all CPUs share (a CPU
        // whose parameters differ stops with 3012 and refreshes nothing).
        let own = params[i].as_ref();
        if let (Some(words), Some(own)) = (
            words_of,
            own.filter(|o| words_of.is_some_and(|w| w.consistent_with(o))),
        ) {
            for (k, (set, mine)) in words.refresh.iter().zip(&own.refresh).enumerate() {
                let dev = |cpu_index: usize| {
                    let w = set.words[cpu_index];
                    let before: u32 = set.words[..cpu_index].iter().sum();
                    let per = if mine.device.is_bit() { 16 } else { 1 };
                    (mine.number + before * per, w * per, w)
                };
                let (first, points, w) = dev(i);
                if w > 0 {
                    plan.publish.push(Copy {
                        from: span(cpu, mine.device, first, points)?,
                        to: shared(cpu, i, words.shared_address(i, k), w)?,
                        words: w as usize,
                    });
                }
                for j in (0..n).filter(|&j| j != i) {
                    let (first, points, w) = dev(j);
                    if w > 0 {
                        plan.import.push(Copy {
                            from: shared(cpu, j, words.shared_address(j, k), w)?,
                            to: span(cpu, mine.device, first, points)?,
                            words: w as usize,
                        });
                    }
                }
            }
        }
        // The own window: the information area, the refresh area and the user area.
        let from_addr = REFRESH_AREA;
        let user = SHARED_MEMORY_WORDS - from_addr;
        for j in (0..n).filter(|&j| j != i) {
            let other = &cpus[j];
            plan.mirror.push((
                j,
                Copy {
                    from: shared(cpu, i, 0, OWN_INFO_WORDS)?,
                    to: shared(other, i, 0, OWN_INFO_WORDS)?,
                    words: OWN_INFO_WORDS as usize,
                },
            ));
            plan.mirror.push((
                j,
                Copy {
                    from: shared(cpu, i, from_addr, user)?,
                    to: shared(other, i, from_addr, user)?,
                    words: user as usize,
                },
            ));
        }
        // Modules this CPU controls: their buffer memory, read by the others.
        let rack = &cpu.config().rack;
        let own_no = i as u32 + 1;
        for slot in rack.slots.iter().filter(|s| s.control_cpu == own_no) {
            for j in (0..n).filter(|&j| j != i) {
                let other = &cpus[j];
                if slot.module.is_some() && slot.buffer_words > 0 {
                    let unit = slot.unit();
                    let from = cpu.memory().map.buffer(unit, 0, slot.buffer_words);
                    let to = other.memory().map.buffer(unit, 0, slot.buffer_words);
                    if let (Ok(f), Ok(t)) = (from, to) {
                        plan.mirror.push((
                            j,
                            Copy {
                                from: span(cpu, DeviceKind::G, f, slot.buffer_words)?,
                                to: span(other, DeviceKind::G, t, slot.buffer_words)?,
                                words: slot.buffer_words as usize,
                            },
                        ));
                    }
                }
                let load = params[j].as_ref();
                if slot.kind.has_inputs() && load.is_some_and(|p| p.out_of_group_input) {
                    plan.io.push((j, slot.start, slot.points, true));
                }
                if slot.kind.has_outputs() && load.is_some_and(|p| p.out_of_group_output) {
                    plan.io.push((j, slot.start, slot.points, false));
                }
            }
        }
        plans.push(plan);
    }
    Ok(plans)
}
