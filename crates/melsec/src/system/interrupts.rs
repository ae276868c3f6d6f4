//! MELSEC-Q's interrupt pointers (004 App. 3, Table 10.5 L7360-7413): their
//! priorities and the error interrupts I32-I39 (§7.15.1, L4997-5022).

use softplc_ir::fault::ErrorCode;

/// 004 App. 3 (L10866-10905): the pointers in priority order, highest first.
/// I32 (1), I34-I36 (2-4), I38 (5), I39 (6); I50-I255 (18-223, I50 first);
/// I16-I27 (224-236); I0-I15 (237-252); I31, I30, I29, I28 (253-256). I33,
/// I37 and I40-I49 are unused and never run.
pub static PRIORITY: [u8; 244] = priority();

const fn priority() -> [u8; 244] {
    let mut order = [0u8; 244];
    let errors = [32u8, 34, 35, 36, 38, 39];
    let mut at = 0;
    while at < errors.len() {
        order[at] = errors[at];
        at += 1;
    }
    let mut n = 50;
    while n <= 255 {
        order[at] = n as u8;
        at += 1;
        n += 1;
    }
    n = 16;
    while n <= 27 {
        order[at] = n as u8;
        at += 1;
        n += 1;
    }
    n = 0;
    while n <= 15 {
        order[at] = n as u8;
        at += 1;
        n += 1;
    }
    n = 31;
    while n >= 28 {
        order[at] = n as u8;
        at += 1;
        n -= 1;
    }
    order
}

/// I32: any error that stops the CPU; it runs before the CPU stops (L5001,
/// L10902 *3).
pub const STOP_ERROR: u32 = 32;

/// The error interrupt of error `code` (004 §7.15.1 L5004-5014): I32 when
/// it stops the CPU, else its class's pointer — I34 UNIT VERIFY ERR., FUSE
/// BREAK OFF, SP.UNIT ERROR; I35 OPERATION ERROR; I36 ICM.OPE.ERROR, FILE
/// OPE.ERROR; I38 PRG.TIME OVER; I39 annunciator and CHK. A continuing
/// error of no class (BATTERY ERROR) has none.
pub fn error_interrupt(code: ErrorCode, stops: bool) -> Option<u32> {
    if stops {
        return Some(STOP_ERROR);
    }
    match code.0 {
        // FUSE BREAK OFF, UNIT VERIFY ERR., SP.UNIT ERROR (2110, 2114,
        // 2115: L8994-8997).
        1300 | 2000 | 2110..=2119 => Some(34),
        4100..=4199 => Some(35),
        // FILE OPE. ERROR.
        2410..=2419 => Some(36),
        // PRG.TIME OVER (scan, low-speed scan).
        5010 | 5011 => Some(38),
        // F**** annunciator, <CHK>ERR.
        9000 | 9010 => Some(39),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_pointer_once_in_app3_order() {
        let mut seen = [false; 256];
        for &n in PRIORITY.iter() {
            assert!(!seen[n as usize], "I{n} twice");
            seen[n as usize] = true;
        }
        let unused: Vec<usize> = (0..256).filter(|&n| !seen[n]).collect();
        let expected: Vec<usize> = [33, 37].into_iter().chain(40..50).collect();
        assert_eq!(unused, expected);
        let rank = |n: u8| PRIORITY.iter().position(|&p| p == n).unwrap();
        // App. 3: I39 (6) before I50 (18), I255 (223) before I16 (224),
        // I27 (236) before I0 (237), I15 (252) before I31 (253), I28 last.
        assert!(rank(39) < rank(50) && rank(255) < rank(16));
        assert!(rank(27) < rank(0) && rank(15) < rank(31));
        assert_eq!(PRIORITY[243], 28);
    }

    #[test]
    fn error_classes() {
        assert_eq!(error_interrupt(ErrorCode(4100), true), Some(32));
        assert_eq!(error_interrupt(ErrorCode(4101), false), Some(35));
        assert_eq!(error_interrupt(ErrorCode(2110), false), Some(34));
        assert_eq!(error_interrupt(ErrorCode(2410), false), Some(36));
        assert_eq!(error_interrupt(ErrorCode(5010), false), Some(38));
        assert_eq!(error_interrupt(ErrorCode(9000), false), Some(39));
        assert_eq!(error_interrupt(ErrorCode(1600), false), None);
    }
}
