//! `softplc test --shard I/N`: a stable split of the scenario files over N
//! independent runs (a Kubernetes Indexed Job, Ray tasks, CI matrix jobs).

use std::path::PathBuf;

/// Shard `index` of `count` (0 ≤ index < count).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    pub index: usize,
    pub count: usize,
}

/// Parses `I/N` (I from 0 to N−1, as Kubernetes' `JOB_COMPLETION_INDEX`).
pub fn parse_shard(text: &str) -> Result<Shard, String> {
    let bad = || format!("invalid shard `{text}`: expected I/N with 0 ≤ I < N, e.g. 0/4");
    let (i, n) = text.split_once('/').ok_or_else(bad)?;
    let index: usize = i.trim().parse().map_err(|_| bad())?;
    let count: usize = n.trim().parse().map_err(|_| bad())?;
    if count == 0 || index >= count {
        return Err(bad());
    }
    Ok(Shard { index, count })
}

impl Shard {
    /// The files of this shard, in their command-line order. The files are
    /// ranked by path (byte order of the path as given, so the result does
    /// not depend on the order of the arguments) and dealt out round-robin:
    /// the file of rank k goes to shard k mod N. Every shard must therefore be
    /// given the same list (as the same glob gives); the N shards then
    /// partition it, and their sizes differ by at most one.
    pub fn select(&self, files: &[PathBuf]) -> Vec<PathBuf> {
        let mut ranked: Vec<usize> = (0..files.len()).collect();
        ranked.sort_by(|&a, &b| {
            files[a]
                .as_os_str()
                .as_encoded_bytes()
                .cmp(files[b].as_os_str().as_encoded_bytes())
                .then(a.cmp(&b))
        });
        let mut mine = vec![false; files.len()];
        for (rank, &i) in ranked.iter().enumerate() {
            mine[i] = rank % self.count == self.index;
        }
        files
            .iter()
            .zip(mine)
            .filter(|(_, m)| *m)
            .map(|(f, _)| f.clone())
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn paths(names: &[&str]) -> Vec<PathBuf> {
        names.iter().map(PathBuf::from).collect()
    }

    #[test]
    fn parses_index_and_count() {
        assert_eq!(parse_shard("0/1"), Ok(Shard { index: 0, count: 1 }));
        assert_eq!(parse_shard("3/4"), Ok(Shard { index: 3, count: 4 }));
        for bad in ["", "1", "4/4", "0/0", "-1/2", "a/2", "1/b", "1/2/3"] {
            assert!(parse_shard(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn deals_sorted_paths_round_robin_keeping_argument_order() {
        let files = paths(&["c.toml", "a.toml", "d.toml", "b.toml", "e.toml"]);
        // Ranks: a 0, b 1, c 2, d 3, e 4.
        let s0 = Shard { index: 0, count: 2 }.select(&files);
        let s1 = Shard { index: 1, count: 2 }.select(&files);
        assert_eq!(s0, paths(&["c.toml", "a.toml", "e.toml"]));
        assert_eq!(s1, paths(&["d.toml", "b.toml"]));
        // The argument order does not change the assignment.
        let mut reversed = files.clone();
        reversed.reverse();
        assert_eq!(
            Shard { index: 1, count: 2 }.select(&reversed),
            paths(&["b.toml", "d.toml"])
        );
    }

    #[test]
    fn one_shard_is_everything_and_extra_shards_are_empty() {
        let files = paths(&["b", "a"]);
        assert_eq!(Shard { index: 0, count: 1 }.select(&files), files);
        assert!(Shard { index: 2, count: 3 }.select(&files).is_empty());
    }
}
