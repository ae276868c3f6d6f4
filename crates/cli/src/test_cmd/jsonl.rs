//! `softplc test --jsonl` lines and `softplc test --merge`: one JSON object
//! per scenario file, so that shards run anywhere can be summed up.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use softplc_sim::scenario::Outcome;

/// One scenario file's result (docs/scenarios.md, "Machine-readable results").
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Line {
    /// The scenario file as given on the command line.
    pub file: String,
    /// The scenario's name (empty when the file did not load).
    pub name: String,
    /// Every assertion passed (and the file loaded and ran).
    pub passed: bool,
    pub assertions: Counts,
    /// Wall-clock seconds for loading, building and running the scenario.
    pub duration_s: f64,
    /// Virtual seconds simulated (scans × scan time).
    pub simulated_s: f64,
    pub scans: u64,
    /// One entry per assertion in file order; a load error or a CPU stop is
    /// one more, failed.
    pub results: Vec<Assertion>,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Counts {
    pub passed: usize,
    pub failed: usize,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Assertion {
    pub text: String,
    pub passed: bool,
    pub detail: String,
    /// The scenario did not load, its CPU stopped or a plant model failed:
    /// an error of the run rather than an expectation that failed (JUnit's
    /// `error`). Absent when false.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub error: bool,
}

impl Line {
    /// The line of a scenario that ran; `extra_failures` are failed
    /// artifact writes (trace CSV, plot), reported after the assertions.
    pub fn of_outcome(file: &Path, o: &Outcome, extra_failures: &[String], wall: f64) -> Line {
        let mut results: Vec<Assertion> = o
            .results
            .iter()
            .map(|r| Assertion {
                text: r.text.clone(),
                passed: r.passed,
                detail: r.detail.clone(),
                error: r.error,
            })
            .collect();
        results.extend(extra_failures.iter().map(|e| Assertion {
            text: e.clone(),
            passed: false,
            detail: String::new(),
            error: false,
        }));
        let failed = results.iter().filter(|r| !r.passed).count();
        Line {
            file: file.display().to_string(),
            name: o.name.clone(),
            passed: failed == 0,
            assertions: Counts {
                passed: results.len() - failed,
                failed,
            },
            duration_s: wall,
            simulated_s: o.simulated_us() as f64 / 1e6,
            scans: o.scans,
            results,
        }
    }

    /// The line of a scenario file that did not load or build.
    pub fn of_error(file: &Path, error: &str, wall: f64) -> Line {
        Line {
            file: file.display().to_string(),
            name: String::new(),
            passed: false,
            assertions: Counts {
                passed: 0,
                failed: 1,
            },
            duration_s: wall,
            simulated_s: 0.0,
            scans: 0,
            results: vec![Assertion {
                text: error.to_string(),
                passed: false,
                detail: String::new(),
                error: true,
            }],
        }
    }

    /// A line read back is one `of_outcome` or `of_error` wrote: its counts
    /// are those of its results, and it passed when none failed. So counts
    /// are bounded by the line's length and a total never wraps.
    fn check(&self) -> Result<(), String> {
        let failed = self.results.iter().filter(|r| !r.passed).count();
        let passed = self.results.len() - failed;
        if self.assertions != (Counts { passed, failed }) {
            return Err(format!(
                "assertions {{\"passed\": {}, \"failed\": {}}} are not the counts of its {} results ({passed} passed, {failed} failed)",
                self.assertions.passed,
                self.assertions.failed,
                self.results.len()
            ));
        }
        if self.passed != (failed == 0) {
            return Err(format!(
                "\"passed\": {} with {failed} failed results",
                self.passed
            ));
        }
        Ok(())
    }

    /// The line as compact JSON (no newline).
    pub fn to_json(&self) -> String {
        // A struct of strings and numbers always serializes.
        serde_json::to_string(self).unwrap_or_default()
    }
}

/// Reads the JSON lines of `files` (blank lines skipped) and returns them
/// sorted by scenario file. A scenario file that appears twice (overlapping
/// shards) is an error, as is a line that is not a result line: counts that
/// are not whole numbers, or not those of the line's own results.
pub fn merge(files: &[PathBuf]) -> Result<Vec<Line>, String> {
    let mut lines = Vec::new();
    for f in files {
        let text =
            std::fs::read_to_string(f).map_err(|e| format!("{}: cannot read: {e}", f.display()))?;
        for (n, l) in text.lines().enumerate() {
            if l.trim().is_empty() {
                continue;
            }
            let at = || format!("{}:{}", f.display(), n + 1);
            let line: Line =
                serde_json::from_str(l).map_err(|e| format!("{}: not a result line: {e}", at()))?;
            line.check().map_err(|e| format!("{}: {e}", at()))?;
            lines.push(line);
        }
    }
    lines.sort_by(|a, b| a.file.cmp(&b.file));
    if let Some(w) = lines.windows(2).find(|w| w[0].file == w[1].file) {
        return Err(format!(
            "{} has two results (do the shards overlap?)",
            w[0].file
        ));
    }
    Ok(lines)
}

/// The text summary of merged lines: one line per scenario file, the failed
/// assertions under it, and the assertion totals as `softplc test` prints
/// them.
pub fn summary(lines: &[Line]) -> (String, Counts) {
    let mut s = String::new();
    let mut total = Counts::default();
    for l in lines {
        s += &format!(
            "{} {} — {}: {} passed, {} failed, {} s simulated in {:.2} s\n",
            if l.passed { "PASS" } else { "FAIL" },
            l.file,
            l.name,
            l.assertions.passed,
            l.assertions.failed,
            l.simulated_s,
            l.duration_s
        );
        for r in l.results.iter().filter(|r| !r.passed) {
            s += &format!("  FAIL {}: {}\n", r.text, r.detail);
        }
        total.passed = total.passed.saturating_add(l.assertions.passed);
        total.failed = total.failed.saturating_add(l.assertions.failed);
    }
    s += &format!("{} passed, {} failed\n", total.passed, total.failed);
    (s, total)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(file: &str, passed: usize, failed: usize) -> Line {
        Line {
            file: file.into(),
            name: format!("{file} name"),
            passed: failed == 0,
            assertions: Counts { passed, failed },
            duration_s: 0.5,
            simulated_s: 40.0,
            scans: 4000,
            results: (0..passed + failed)
                .map(|i| Assertion {
                    text: format!("check {i}"),
                    passed: i < passed,
                    detail: "got 1".into(),
                    error: false,
                })
                .collect(),
        }
    }

    #[test]
    fn lines_round_trip_and_merge_sorted_with_totals() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("a.jsonl");
        let b = dir.path().join("b.jsonl");
        std::fs::write(&a, format!("{}\n\n", line("z.toml", 3, 0).to_json())).unwrap();
        std::fs::write(
            &b,
            format!(
                "{}\n{}\n",
                line("y.toml", 2, 1).to_json(),
                line("x.toml", 4, 0).to_json()
            ),
        )
        .unwrap();
        let merged = merge(&[a, b]).unwrap();
        let files: Vec<&str> = merged.iter().map(|l| l.file.as_str()).collect();
        assert_eq!(files, ["x.toml", "y.toml", "z.toml"]);
        assert_eq!(merged[1], line("y.toml", 2, 1));
        let (text, total) = summary(&merged);
        assert_eq!(
            total,
            Counts {
                passed: 9,
                failed: 1
            }
        );
        assert!(text.ends_with("\n9 passed, 1 failed\n"), "{text}");
        assert!(
            text.contains("FAIL y.toml — y.toml name: 2 passed, 1 failed, 40 s simulated in 0.50 s\n  FAIL check 2: got 1\n"),
            "{text}"
        );
    }

    #[test]
    fn overlapping_shards_and_bad_lines_are_errors_naming_the_place() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("a.jsonl");
        std::fs::write(&a, line("x.toml", 1, 0).to_json()).unwrap();
        let err = merge(&[a.clone(), a.clone()]).unwrap_err();
        assert!(err.contains("x.toml has two results"), "{err}");
        let bad = dir.path().join("bad.jsonl");
        std::fs::write(
            &bad,
            format!("{}\n{{\"file\": 1}}\n", line("x.toml", 1, 0).to_json()),
        )
        .unwrap();
        let err = merge(&[bad]).unwrap_err();
        assert!(err.contains("bad.jsonl:2: not a result line"), "{err}");
        let mut huge = line("y.toml", 1, 1);
        huge.assertions.failed = usize::MAX;
        let wrapped = dir.path().join("wrapped.jsonl");
        std::fs::write(
            &wrapped,
            format!("{}\n{}\n", line("x.toml", 1, 0).to_json(), huge.to_json()),
        )
        .unwrap();
        let err = merge(&[wrapped]).unwrap_err();
        assert!(err.contains("wrapped.jsonl:2: assertions"), "{err}");
        let mut liar = line("y.toml", 1, 1);
        liar.passed = true;
        let lying = dir.path().join("lying.jsonl");
        std::fs::write(&lying, liar.to_json()).unwrap();
        let err = merge(&[lying]).unwrap_err();
        assert!(
            err.contains("lying.jsonl:1: \"passed\": true with 1 failed"),
            "{err}"
        );
        let err = merge(&[dir.path().join("missing.jsonl")]).unwrap_err();
        assert!(err.contains("missing.jsonl: cannot read"), "{err}");
    }
}
