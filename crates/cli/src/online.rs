//! `serve`'s program files written during RUN (contract §7): the sources
//! `PUT /api/v1/program` may write, and `--watch`.

use std::sync::Arc;

use softplc_serve::online::{self, Online};
use softplc_serve::ServeState;

/// What keeps `--watch` going until serve ends.
pub type Watching = Option<online::Watcher>;

/// The program files of `program` as `state` runs them, and with `watch`
/// the watcher (its END hook added to `state`). Without `--watch` a
/// program whose sources cannot be listed is only a note: the API then
/// answers that there is nothing to write.
pub fn setup(
    program: &std::path::Path,
    watch: bool,
    state: &mut ServeState,
) -> Result<(Option<Arc<Online>>, Watching), String> {
    let sources = match softplc_core::online::Sources::load(program, &state.cpus) {
        Ok(s) => s,
        Err(e) if watch => return Err(format!("--watch: {e}")),
        Err(e) => {
            eprintln!("softplc: programs cannot be written during RUN: {e}");
            return Ok((None, None));
        }
    };
    let manifests = sources.manifests().to_vec();
    let online = Arc::new(Online::new(sources));
    if !watch {
        return Ok((Some(online), None));
    }
    let w = online::watch(online.clone(), manifests)?;
    state.add_hook(w.hook);
    Ok((Some(online), Some(w.watcher)))
}
