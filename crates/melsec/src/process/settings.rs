//! The process CPU's decisions (spec/process-control.md "Decisions in one
//! place", DEC-1 … DEC-36): where the manual's text is lost or ambiguous the
//! spec chose one behaviour; each choice is one named setting here, the
//! spec's choice being `true`, so a user who owns a real CPU can match it.
//! plc.toml `[process]` sets them (`firmware_serial_ge_07032 = false`); the
//! instructions read them when they compile (`Args::setting`), so a choice
//! costs nothing in the scan. COMPATIBILITY.md lists them from [`KEYS`].

macro_rules! decisions {
    ($($(#[doc = $doc:literal])+ $dec:literal $name:ident,)*) => {
        /// One `bool` per decision; `true` (the default) is the spec's choice.
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        pub struct ProcessSettings {
            $($(#[doc = $doc])+ pub $name: bool,)*
        }

        impl Default for ProcessSettings {
            fn default() -> Self {
                ProcessSettings { $($name: true,)* }
            }
        }

        /// Every setting: plc.toml key, decision number, what `true` means.
        pub static KEYS: &[Key] = &[
            $(Key { name: stringify!($name), dec: $dec, doc: concat!($($doc),+) },)*
        ];

        impl ProcessSettings {
            /// Sets the setting named `key`; false when there is none.
            pub fn set(&mut self, key: &str, value: bool) -> bool {
                match key {
                    $(stringify!($name) => self.$name = value,)*
                    _ => return false,
                }
                true
            }

            /// The value of the setting named `key`.
            pub fn get(&self, key: &str) -> Option<bool> {
                match key {
                    $(stringify!($name) => Some(self.$name),)*
                    _ => None,
                }
            }
        }
    };
}

/// A setting's documentation.
#[derive(Debug)]
pub struct Key {
    pub name: &'static str,
    /// The spec's decision number (DEC-n).
    pub dec: u8,
    pub doc: &'static str,
}

decisions! {
    /// Period counters: the start execution loads the counter and is time 0,
    /// never a reach (false: the start execution is also a reach).
    1 counter_start_is_time_zero,
    /// N = round(P/ΔT), halves up (false: the integer part).
    2 period_count_rounds,
    /// A change of the period or ΔT takes effect when the period in progress
    /// ends (false: an up-count compared with the current N every execution).
    3 period_change_at_reach,
    /// Executions that end before the judgment step do not start or advance
    /// counters (false: they advance them).
    4 early_end_skips_counters,
    /// MODE: LCC = b0, LCM = b2 (false: LCM = b0, LCC = b2).
    5 mode_lcc_b0,
    /// INH: ERRI = b15, TRKF = b14 (false: ERRI = b14, TRKF = b15).
    6 inh_erri_b15,
    /// ALM2 (+116): MHA2 = b1, MLA2 = b0 (false: MHA2 = b0, MLA2 = b1).
    7 alm2_mha2_b1,
    /// "Previous BW/BB" is the block memory D1 as found, no hidden copy.
    8 previous_in_block_memory,
    /// S.IN: BB1 = SEA = BB2 ∨ BB3 after both range checks.
    9 in_sea_after_both_checks,
    /// S.OUT1/S.OUT2/S.DUTY/S.PIDP: when T = MV the rate limiter and reset
    /// windup are skipped and their alarm bits keep their values.
    10 output_tracking_skips_limits,
    /// Reset windup: first-order pull-back of MVP toward MH/ML with ΔT/TI.
    11 reset_windup_first_order,
    /// S.DUTY: ON count = round(MV/100·N), recomputed only at period reach.
    12 duty_on_count_rounds,
    /// S.PSUM: increment is the first of (E1 − E1n-1) mod 2^32/2^24/2^16 that
    /// is ≤ 32767, else 0.
    13 psum_wraparound,
    /// Cascade SV setting writes SVn to SV (+14).
    14 cascade_writes_sv,
    /// Firmware serial ≥ 07032: anti-windup on MHA2/MLA2 and the S.PIDP
    /// extras (false: ≤ 07031, MHA/MLA).
    15 firmware_serial_ge_07032,
    /// S.BPI: the reconstructed blend-PI form.
    16 bpi_reconstructed,
    /// S.R: BW = E1·(Rn − RMIN)/(RMAX − RMIN) + BIAS.
    17 ratio_reconstructed,
    /// S.PHPL/S.BC change rate: reference at start, evaluated and re-taken
    /// every m executions, alarms held in between.
    18 change_rate_window,
    /// S.PHPL: BB1 = BB2 ∨ BB3 ∨ BB4 ∨ BB5; HHA/LLA only in ALM.
    19 phpl_bb1_or,
    /// S.LLAG and S.D: E1n-1 := E1 on every execution, also while e1 = 1.
    20 lag_tracks_input_always,
    /// S.DED: sample at the start and every N executions, output the oldest
    /// sample before pushing.
    21 ded_output_before_push,
    /// S.DED without a 1→0 edge starts at the first execution, no fill value.
    22 ded_start_without_edge,
    /// S.DED while e1 = 1: BW = E1, BB1 = 0, no sampling, count reset.
    23 ded_bypass_resets,
    /// S.DED OCHG: 0 → fill with E1 at the edge, 1 → fill with Ys.
    24 ded_ochg_fill,
    /// S.VLMT2: the literal table (hold while the rate is exceeded).
    25 vlmt2_literal,
    /// S.FLT: start on the first execution and whenever ST or SN changes;
    /// mean output only when full.
    26 flt_restart_on_change,
    /// S.TPC: A1 = (B1 + T′)/(B1 + E2), A2 = (B2 + E3)/(B2 + P′); e1/e2 = 1
    /// means used.
    27 tpc_reconstructed,
    /// S.IENG with RH < RL applies the formula (false: BW holds).
    28 ieng_decreasing,
    /// S.ADD/SUB/MUL: input n sets the term count; both n words range-checked.
    29 arith_input_n,
    /// S.ADD/SUB/MUL: the bias B is added (false: subtracted).
    30 arith_bias_added,
    /// Comparisons: complementary reset edges, HS < 0 checked, inclusive
    /// boundaries as the spec reads them.
    31 compare_complementary,
    /// S.AT1: the step execution starts the sampling counter (sample 0).
    32 at1_step_starts_sampling,
    /// S.AT1: D3+18 stores R = |R′|/100 (false: R′).
    33 at1_stores_r,
    /// S.AT1: every MV restore clears the step flag; every ending and the
    /// (0,0) branch clear the counter flags.
    34 at1_restore_clears_flags,
    /// S.AT1: BB1 = BB2 ∨ … ∨ BB8.
    35 at1_bb1_or,
    /// SD1502 detail codes: negative → 2, count out of range → 3, count >
    /// 32767 → 4, divisor 0 → 5; the instruction stops at the failing step.
    36 detail_codes,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_key_per_decision_in_order_all_true_by_default() {
        let d: Vec<u8> = KEYS.iter().map(|k| k.dec).collect();
        assert_eq!(d, (1..=36).collect::<Vec<u8>>());
        let s = ProcessSettings::default();
        assert!(KEYS.iter().all(|k| s.get(k.name) == Some(true)));
        let mut s = s;
        assert!(s.set("firmware_serial_ge_07032", false));
        assert!(!s.firmware_serial_ge_07032);
        assert!(!s.set("no_such_key", true));
    }
}
