//! Fitting a recorded step test from a CSV file (`softplc tune --fit-csv`):
//! columns `t` (or `time`, `time_s`; seconds), `u` (or `mv`; the input) and
//! `y` (or `pv`; the output), one sample a line, a header line first.
//!
//! The step is the first sample whose `u` differs from the first sample's;
//! the input is taken as held from each sample to the next (zero-order hold),
//! so the process sees the step from that sample's time. The steady output
//! before the step is the mean `y` of the second half of the samples before
//! it; the record ends before any second change of `u`.

use serde::Serialize;

use crate::fit::{fit_fopdt, FopdtFit, StepResponse};

/// The result of a CSV fit.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CsvFit {
    pub file: String,
    /// Time of the step, s.
    pub step_at: f64,
    /// Input before and after the step.
    pub u_before: f64,
    pub u_after: f64,
    /// Steady output before the step.
    pub y_before: f64,
    pub fit: FopdtFit,
}

/// Parses and fits `text` (`file` names it in errors as `FILE:LINE`).
pub fn fit_csv_text(text: &str, file: &str) -> Result<CsvFit, String> {
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
    let (hline, header) = lines
        .next()
        .ok_or_else(|| format!("{file}: empty (a header `t,u,y` is expected)"))?;
    let names: Vec<String> = header
        .split(',')
        .map(|c| c.trim().to_ascii_lowercase())
        .collect();
    let col = |options: &[&str]| {
        names
            .iter()
            .position(|n| options.contains(&n.as_str()))
            .ok_or_else(|| {
                format!(
                    "{file}:{}: no column {} in the header `{}`",
                    hline + 1,
                    options.join(" or "),
                    header.trim()
                )
            })
    };
    let (ct, cu, cy) = (
        col(&["t", "time", "time_s"])?,
        col(&["u", "mv"])?,
        col(&["y", "pv"])?,
    );
    let mut rows: Vec<(f64, f64, f64)> = Vec::new();
    for (i, line) in lines {
        let cells: Vec<&str> = line.split(',').map(str::trim).collect();
        let get = |c: usize| -> Result<f64, String> {
            let cell = cells.get(c).ok_or_else(|| {
                format!(
                    "{file}:{}: {} cells, column {} missing",
                    i + 1,
                    cells.len(),
                    c + 1
                )
            })?;
            match cell.parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(v),
                _ => Err(format!("{file}:{}: `{cell}` is not a number", i + 1)),
            }
        };
        let row = (get(ct)?, get(cu)?, get(cy)?);
        if let Some(prev) = rows.last() {
            if row.0 <= prev.0 {
                return Err(format!(
                    "{file}:{}: time {} does not increase (previous {})",
                    i + 1,
                    row.0,
                    prev.0
                ));
            }
        }
        rows.push(row);
    }
    let u0 = rows
        .first()
        .map(|r| r.1)
        .ok_or_else(|| format!("{file}: no samples"))?;
    let differs = |a: f64, b: f64| (a - b).abs() > 1e-9 * a.abs().max(b.abs()).max(1e-300);
    let k = rows
        .iter()
        .position(|r| differs(r.1, u0))
        .ok_or_else(|| format!("{file}: the input `u` never changes: no step to fit"))?;
    let u1 = rows[k].1;
    let end = rows[k..]
        .iter()
        .position(|r| differs(r.1, u1))
        .map_or(rows.len(), |e| k + e);
    let before = &rows[k / 2..k];
    let y0 = before.iter().map(|r| r.2).sum::<f64>() / before.len() as f64;
    let step_at = rows[k].0;
    let data = StepResponse {
        t: rows[k..end].iter().map(|r| r.0 - step_at).collect(),
        y: rows[k..end].iter().map(|r| r.2).collect(),
        y0,
        du: u1 - u0,
    };
    let fit = fit_fopdt(&data).map_err(|e| format!("{file}: {e}"))?;
    Ok(CsvFit {
        file: file.to_string(),
        step_at,
        u_before: u0,
        u_after: u1,
        y_before: y0,
        fit,
    })
}

/// Reads and fits a CSV file.
pub fn fit_csv_file(path: &std::path::Path) -> Result<CsvFit, String> {
    const MAX_BYTES: u64 = 64 << 20;
    let bytes = softplc_core::program::read_limited(path, MAX_BYTES, "a CSV file")
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let text =
        String::from_utf8(bytes).map_err(|e| format!("{}: not UTF-8 text: {e}", path.display()))?;
    fit_csv_text(&text, &path.display().to_string())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::fopdt_step;

    #[test]
    fn a_step_in_csv() {
        let mut s = String::from("time_s,mv,pv\n");
        for i in 0..600 {
            let t = i as f64 * 0.5;
            let u = if t >= 20.0 { 30.0 } else { 10.0 };
            let y = fopdt_step(1.5, 25.0, 4.0, 20.0, 5.0, t - 20.0);
            s += &format!("{t},{u},{y}\n");
        }
        let f = fit_csv_text(&s, "x.csv").unwrap();
        assert_eq!(
            (f.step_at, f.u_before, f.u_after, f.y_before),
            (20.0, 10.0, 30.0, 5.0)
        );
        assert!((f.fit.gain - 1.5).abs() < 1e-6 && (f.fit.tau - 25.0).abs() < 1e-4);
        assert!((f.fit.dead_time - 4.0).abs() < 1e-4, "{f:?}");
    }

    #[test]
    fn errors_name_file_and_line() {
        assert!(fit_csv_text("", "a.csv")
            .unwrap_err()
            .starts_with("a.csv: empty"));
        let e = fit_csv_text("t,x,y\n0,1,2\n", "a.csv").unwrap_err();
        assert!(e.contains("a.csv:1: no column u or mv"), "{e}");
        let e = fit_csv_text("t,u,y\n0,1,2\n1,1,zz\n", "a.csv").unwrap_err();
        assert!(e.contains("a.csv:3: `zz` is not a number"), "{e}");
        let e = fit_csv_text("t,u,y\n0,1,2\n0,1,2\n", "a.csv").unwrap_err();
        assert!(e.contains("a.csv:3: time 0 does not increase"), "{e}");
        let e = fit_csv_text("t,u,y\n0,1,2\n1,1\n", "a.csv").unwrap_err();
        assert!(e.contains("a.csv:3: 2 cells"), "{e}");
        let e = fit_csv_text("t,u,y\n0,1,2\n1,1,2\n", "a.csv").unwrap_err();
        assert!(e.contains("never changes"), "{e}");
        let e = fit_csv_text("t,u,y\n0,1,2\n1,2,2\n", "a.csv").unwrap_err();
        assert!(e.contains("at least 10"), "{e}");
    }
}
