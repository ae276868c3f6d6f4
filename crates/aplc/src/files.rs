//! Several `.apl` files as one user program (contract §1.1 item 10): the
//! `[[program]]` files of an APLC-TCP project, and the global variables of
//! files read before a CPU is built (scenario device names).

use std::path::Path;

use softplc_ir::ops::{file_line, Program};
use softplc_lang::{Diagnostic, Diagnostics, Token};

use crate::{compile, globals_of, pou, text};

/// The global variables of `.apl` files, sorted by name (for tools that
/// resolve names before building a CPU, e.g. scenario files); files that do
/// not parse give none (their errors come when the program is loaded).
pub fn globals_of_files(paths: &[&Path]) -> Vec<(String, String)> {
    let mut out = Vec::new();
    for p in paths {
        let Ok(bytes) = softplc_lang::read_limited(p, softplc_lang::MAX_IL_BYTES, "a program file")
        else {
            continue;
        };
        let name = p.display().to_string();
        let text = text::decode(&bytes);
        let Ok(lines) = text::lines(&name, &text) else {
            continue;
        };
        if let Ok(unit) = pou::parse(&name, &lines, &crate::is_mnemonic) {
            out.extend(globals_of(&unit));
        }
    }
    out.sort();
    out
}

/// Loads the `.apl` files of an APLC-TCP project as ONE user program
/// (contract §1.1 item 10): the POUs and global tables of all files
/// together, exactly one MAIN. Each file keeps its own rules: its global
/// table before its first POU or instruction, a file without POU headers is
/// a MAIN, a file with headers has nothing before its first one. Every
/// diagnostic, and every run-time error location
/// ([`Program::sources`]), names the file and
/// its own line.
pub fn load_files(paths: &[&Path]) -> Result<Program, Diagnostics> {
    load_files_with(paths, None)
}

/// [`load_files`] with one file's text given instead of read (`(path,
/// bytes)`): a file written during RUN, compiled with the others before it
/// replaces the running program.
pub fn load_files_with(
    paths: &[&Path],
    given: Option<(&Path, &[u8])>,
) -> Result<Program, Diagnostics> {
    let read = |path: &Path| match given {
        Some((p, bytes)) if p == path => Ok(bytes.to_vec()),
        _ => softplc_lang::read_limited(path, softplc_lang::MAX_IL_BYTES, "a program file"),
    };
    if let [one] = paths {
        let name = one.display().to_string();
        let bytes = read(one).map_err(|e| compile::file_error(&name, e))?;
        return crate::load_bytes(&name, &bytes);
    }
    let mut diags = Vec::new();
    // (first line in the combined numbering, file name).
    let mut sources: Vec<(u32, String)> = Vec::new();
    let (mut globals, mut bodies) = (Vec::new(), Vec::new());
    let mut offset = 0u32;
    for path in paths {
        let name = path.display().to_string();
        let bytes = match read(path) {
            Ok(b) => b,
            Err(e) => {
                diags.push(Diagnostic {
                    file: name,
                    line: 0,
                    col: 0,
                    message: e,
                });
                continue;
            }
        };
        let text = text::decode(&bytes);
        let mut lines = match text::lines(&name, &text) {
            Ok(l) => l,
            Err(d) => {
                diags.push(d);
                continue;
            }
        };
        // Lines are numbered through the files one after the other.
        let base = offset;
        for t in lines.iter_mut().flatten() {
            t.line += base;
        }
        sources.push((base + 1, name.clone()));
        offset += text.split('\n').count() as u32;
        let is = |l: &[Token], k: &str| l[0].text.eq_ignore_ascii_case(k);
        // The file's leading global tables go first in the combined program.
        let mut rest = lines.as_slice();
        while rest.first().is_some_and(|l| is(l, "VAR_GLOBAL")) {
            let end = rest
                .iter()
                .position(|l| is(l, "END_VAR"))
                .map_or(rest.len(), |e| e + 1);
            globals.extend_from_slice(&rest[..end]);
            rest = &rest[end..];
        }
        let Some(first) = rest.first() else { continue };
        if !lines.iter().any(|l| is(l, "POU")) {
            // A file without headers is the MAIN program.
            let at = |text: &str| Token {
                text: text.into(),
                line: first[0].line,
                col: first[0].col,
            };
            bodies.push(vec![at("POU"), at("MAIN")]);
        } else if !is(first, "POU") {
            diags.push(Diagnostic::at(
                &name,
                &Token {
                    line: first[0].line - base,
                    ..first[0].clone()
                },
                format!(
                    "`{}` before the first POU header of the file (contract §1.1 item 7)",
                    first[0].text
                ),
            ));
        }
        bodies.extend_from_slice(rest);
    }
    if !diags.is_empty() {
        return Err(Diagnostics(diags));
    }
    let Some(label) = sources.first().map(|s| s.1.clone()) else {
        return Err(Diagnostics(vec![Diagnostic {
            file: String::new(),
            line: 0,
            col: 0,
            message: "no program file".into(),
        }]));
    };
    let remap =
        |d: Vec<Diagnostic>| Diagnostics(d.into_iter().map(|d| locate(&sources, d)).collect());
    globals.extend(bodies);
    let unit = pou::parse(&label, &globals, &crate::is_mnemonic).map_err(remap)?;
    let mut program = compile::compile(&label, &unit).map_err(|d| remap(d.0))?;
    program.sources = sources;
    program.globals = globals_of(&unit);
    Ok(program)
}

/// A diagnostic of the combined program at its file and own line; a `line N`
/// in the message (a first definition) too, naming the file when it is
/// another one.
fn locate(sources: &[(u32, String)], mut d: Diagnostic) -> Diagnostic {
    let at = |line: u32| file_line(sources, line);
    if let Some((file, line)) = at(d.line.max(1)) {
        let own = file.to_string();
        let mut msg = String::new();
        let mut rest = d.message.as_str();
        while let Some(i) = rest.find("line ") {
            let digits = rest[i + 5..]
                .chars()
                .take_while(|c| c.is_ascii_digit())
                .count();
            msg.push_str(&rest[..i]);
            match rest[i + 5..i + 5 + digits].parse::<u32>().ok().and_then(at) {
                Some((f, l)) if f == own => msg.push_str(&format!("line {l}")),
                Some((f, l)) => msg.push_str(&format!("{f}:{l}")),
                None => msg.push_str(&rest[i..i + 5 + digits]),
            }
            rest = &rest[i + 5 + digits..];
        }
        msg.push_str(rest);
        d.message = msg;
        if d.line > 0 {
            d.line = line;
        }
        d.file = own;
    }
    d
}
