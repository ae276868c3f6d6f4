//! `softplc test --junit FILE`: the results as JUnit XML, the report format
//! CI systems (GitHub Actions, GitLab, Jenkins) read. Built from the
//! `--jsonl` lines, so a run and a `--merge` of shards write the same report.
//!
//! One `testsuite` per scenario file (named by the file as given), one
//! `testcase` per assertion; a failed assertion has a `failure` whose message
//! gives the expected and the actual value, and a scenario that does not load,
//! whose CPU stops or whose plant model fails has an `error`.

use std::path::Path;

use quick_xml::events::{BytesDecl, BytesText, Event};
use quick_xml::Writer;

use super::jsonl::{Assertion, Line};

/// Counts of a suite or of the whole report.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Tally {
    tests: usize,
    failures: usize,
    errors: usize,
}

impl Tally {
    fn of(results: &[Assertion]) -> Tally {
        let errors = results.iter().filter(|r| !r.passed && r.error).count();
        let failed = results.iter().filter(|r| !r.passed).count();
        Tally {
            tests: results.len(),
            failures: failed - errors,
            errors,
        }
    }

    fn add(self, o: Tally) -> Tally {
        Tally {
            tests: self.tests + o.tests,
            failures: self.failures + o.failures,
            errors: self.errors + o.errors,
        }
    }
}

/// The JUnit XML of `lines`, one suite per line in the given order.
pub fn report(lines: &[Line]) -> String {
    let mut w = Writer::new_with_indent(Vec::new(), b' ', 2);
    // Writing into a Vec cannot fail.
    let _ = write_report(&mut w, lines);
    let mut xml = String::from_utf8(w.into_inner()).unwrap_or_default();
    xml.push('\n');
    xml
}

fn write_report(w: &mut Writer<Vec<u8>>, lines: &[Line]) -> std::io::Result<()> {
    w.write_event(Event::Decl(BytesDecl::new("1.0", Some("UTF-8"), None)))?;
    let total = lines
        .iter()
        .map(|l| Tally::of(&l.results))
        .fold(Tally::default(), Tally::add);
    let time: f64 = lines.iter().map(|l| l.duration_s).sum();
    w.create_element("testsuites")
        .with_attributes([
            ("name", "softplc test"),
            ("tests", &total.tests.to_string()),
            ("failures", &total.failures.to_string()),
            ("errors", &total.errors.to_string()),
            ("time", &seconds(time)),
        ])
        .write_inner_content(|w| {
            for l in lines {
                write_suite(w, l)?;
            }
            Ok(())
        })?;
    Ok(())
}

fn write_suite(w: &mut Writer<Vec<u8>>, l: &Line) -> std::io::Result<()> {
    let t = Tally::of(&l.results);
    // Reports group cases by class name: the scenario's name, else its file.
    let class = if l.name.is_empty() { &l.file } else { &l.name };
    w.create_element("testsuite")
        .with_attributes([
            ("name", l.file.as_str()),
            ("tests", &t.tests.to_string()),
            ("failures", &t.failures.to_string()),
            ("errors", &t.errors.to_string()),
            ("skipped", "0"),
            ("time", &seconds(l.duration_s)),
        ])
        .write_inner_content(|w| {
            w.create_element("properties").write_inner_content(|w| {
                for (name, value) in [
                    ("scenario", l.name.clone()),
                    ("simulated_s", l.simulated_s.to_string()),
                    ("scans", l.scans.to_string()),
                ] {
                    w.create_element("property")
                        .with_attributes([("name", name), ("value", value.as_str())])
                        .write_empty()?;
                }
                Ok(())
            })?;
            for r in &l.results {
                write_case(w, class, r)?;
            }
            Ok(())
        })?;
    Ok(())
}

fn write_case(w: &mut Writer<Vec<u8>>, class: &str, r: &Assertion) -> std::io::Result<()> {
    let case = w
        .create_element("testcase")
        .with_attributes([("name", r.text.as_str()), ("classname", class)]);
    if r.passed {
        case.write_empty()?;
        return Ok(());
    }
    case.write_inner_content(|w| {
        let (element, message) = if r.error {
            let why = if r.detail.is_empty() {
                r.text.clone()
            } else {
                format!("{}: {}", r.text, r.detail)
            };
            ("error", why)
        } else if r.detail.is_empty() {
            ("failure", format!("expected {}", r.text))
        } else {
            ("failure", format!("expected {}: {}", r.text, r.detail))
        };
        w.create_element(element)
            .with_attributes([("message", message.as_str())])
            .write_text_content(BytesText::new(&message))?;
        Ok(())
    })?;
    Ok(())
}

/// JUnit's `time`: seconds with millisecond resolution.
fn seconds(s: f64) -> String {
    format!("{:.3}", s.max(0.0))
}

/// Writes the report to `path` whole (`online::write_file`: a reader never
/// sees half a report).
pub fn write(path: &Path, lines: &[Line]) -> Result<(), String> {
    softplc_core::online::write_file(path, report(lines).as_bytes())
        .map_err(|e| format!("cannot write {e}"))
}

#[cfg(test)]
mod tests {
    use super::super::jsonl::Counts;
    use super::*;

    fn assertion(text: &str, passed: bool, detail: &str, error: bool) -> Assertion {
        Assertion {
            text: text.into(),
            passed,
            detail: detail.into(),
            error,
        }
    }

    fn line(file: &str, name: &str, results: Vec<Assertion>) -> Line {
        let failed = results.iter().filter(|r| !r.passed).count();
        Line {
            file: file.into(),
            name: name.into(),
            passed: failed == 0,
            assertions: Counts {
                passed: results.len() - failed,
                failed,
            },
            duration_s: 0.25,
            simulated_s: 30.0,
            scans: 3000,
            results,
        }
    }

    #[test]
    fn suites_cases_failures_and_errors_with_their_counts() {
        let lines = [
            line(
                "sim/tank.toml",
                "tank <fill> & drain",
                vec![
                    assertion(
                        "Y0 becomes true within 20 ms after 1 s",
                        true,
                        "at 1 s (scan 100)",
                        false,
                    ),
                    assertion(
                        "D10 = 25 ±1 at 30 s",
                        false,
                        "got 22 at 30 s (scan 3000)",
                        false,
                    ),
                    assertion(
                        "the CPU keeps running (stopped at 2 s, scan 200)",
                        false,
                        "error 4100 OPERATION ERROR at step 12 (main.il:5)",
                        true,
                    ),
                ],
            ),
            line(
                "sim/broken.toml",
                "",
                vec![assertion(
                    "broken.toml:3:1: unknown key \"x\"",
                    false,
                    "",
                    true,
                )],
            ),
        ];
        let xml = report(&lines);
        assert!(
            xml.starts_with("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"),
            "{xml}"
        );
        assert!(
            xml.contains(
                "<testsuites name=\"softplc test\" tests=\"4\" failures=\"1\" errors=\"2\" time=\"0.500\">"
            ),
            "{xml}"
        );
        assert!(
            xml.contains(
                "<testsuite name=\"sim/tank.toml\" tests=\"3\" failures=\"1\" errors=\"1\" skipped=\"0\" time=\"0.250\">"
            ),
            "{xml}"
        );
        // Markup in names is escaped; the class is the scenario's name.
        assert!(
            xml.contains(
                "<testcase name=\"Y0 becomes true within 20 ms after 1 s\" classname=\"tank &lt;fill&gt; &amp; drain\"/>"
            ),
            "{xml}"
        );
        assert!(
            xml.contains(
                "<failure message=\"expected D10 = 25 ±1 at 30 s: got 22 at 30 s (scan 3000)\">"
            ),
            "{xml}"
        );
        assert!(
            xml.contains("<error message=\"the CPU keeps running (stopped at 2 s, scan 200): error 4100 OPERATION ERROR at step 12 (main.il:5)\">"),
            "{xml}"
        );
        // A file that did not load: its class is the file, its case an error.
        assert!(
            xml.contains("<testcase name=\"broken.toml:3:1: unknown key &quot;x&quot;\" classname=\"sim/broken.toml\">"),
            "{xml}"
        );
        assert!(
            xml.contains("<property name=\"simulated_s\" value=\"30\"/>"),
            "{xml}"
        );
    }

    #[test]
    fn written_whole_and_a_bad_place_is_an_error_naming_it() {
        let dir = tempfile::tempdir().unwrap();
        let f = dir.path().join("report.xml");
        write(
            &f,
            &[line(
                "a.toml",
                "a",
                vec![assertion("M0 is ON", true, "", false)],
            )],
        )
        .unwrap();
        let text = std::fs::read_to_string(&f).unwrap();
        assert!(
            text.contains("tests=\"1\" failures=\"0\" errors=\"0\""),
            "{text}"
        );
        let bad = dir.path().join("no/such/dir/report.xml");
        let err = write(&bad, &[]).unwrap_err();
        assert!(
            err.starts_with("cannot write ") && err.contains("no/such/dir/report.xml"),
            "{err}"
        );
    }
}
