use super::*;
use std::sync::atomic::{AtomicUsize, Ordering};

/// A fresh directory under the system temp dir, removed on drop.
struct TempDir(PathBuf);

impl TempDir {
    fn new(tag: &str) -> TempDir {
        TempDir::new_in(std::env::temp_dir(), tag)
    }
    /// In memory (`/dev/shm`) where available: for tests that create thousands of
    /// files, which on a busy disk costs milliseconds each.
    fn new_fast(tag: &str) -> TempDir {
        let shm = Path::new("/dev/shm");
        if shm.is_dir() {
            TempDir::new_in(shm.to_path_buf(), tag)
        } else {
            TempDir::new(tag)
        }
    }
    fn new_in(base: PathBuf, tag: &str) -> TempDir {
        static N: AtomicUsize = AtomicUsize::new(0);
        let dir = base.join(format!(
            "softplc-persist-{tag}-{}-{}",
            std::process::id(),
            N.fetch_add(1, Ordering::Relaxed)
        ));
        let _ = fs::remove_dir_all(&dir);
        TempDir(dir)
    }
    fn path(&self) -> &Path {
        &self.0
    }
    fn journal(&self) -> PathBuf {
        self.0.join(JOURNAL_FILE)
    }
    fn image(&self) -> PathBuf {
        self.0.join(IMAGE_FILE)
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = fs::remove_dir_all(&self.0);
    }
}

fn layout() -> Vec<Region> {
    vec![
        Region::new("latch:D", 2000),
        Region::new("zr", 64 * 1024),
        Region::new("history", 700),
        Region::new("clock", 8),
    ]
}

/// Region contents derived from a seed, all bytes different between seeds.
fn contents(layout: &[Region], seed: u8) -> Vec<Vec<u8>> {
    layout
        .iter()
        .enumerate()
        .map(|(i, r)| {
            (0..r.len)
                .map(|j| (j as u8).wrapping_mul(7) ^ seed ^ (i as u8))
                .collect()
        })
        .collect()
}

fn refs(v: &[Vec<u8>]) -> Vec<&[u8]> {
    v.iter().map(Vec::as_slice).collect()
}

fn some(v: &[Vec<u8>]) -> Vec<Option<Vec<u8>>> {
    v.iter().cloned().map(Some).collect()
}

fn frame_len(runs: &[usize]) -> usize {
    format::FRAME_HEAD + runs.iter().map(|n| format::RECORD_HEAD + n).sum::<usize>() + 4
}

#[test]
fn fresh_store_returns_none_and_no_warnings() {
    let t = TempDir::new("fresh");
    let (store, got) = Store::open(t.path(), &layout()).unwrap();
    assert_eq!(got, vec![None; 4]);
    assert!(store.warnings().is_empty(), "{:?}", store.warnings());
    assert_eq!(store.generation(), 0);
    assert!(t.image().exists());
    // Reopening before any commit: still nothing committed.
    drop(store);
    let (store, got) = Store::open(t.path(), &layout()).unwrap();
    assert_eq!(got, vec![None; 4]);
    assert!(store.warnings().is_empty());
}

#[test]
fn round_trip_several_regions() {
    let t = TempDir::new("roundtrip");
    let l = layout();
    let (mut store, _) = Store::open(t.path(), &l).unwrap();
    let a = contents(&l, 1);
    let s = store.commit(&refs(&a)).unwrap();
    assert_eq!(s.generation, 1);
    let b = contents(&l, 2);
    let s = store.commit(&refs(&b)).unwrap();
    assert_eq!(s.generation, 2);
    drop(store);
    let (store, got) = Store::open(t.path(), &l).unwrap();
    assert_eq!(got, some(&b));
    assert_eq!(store.generation(), 2);
    assert!(store.warnings().is_empty(), "{:?}", store.warnings());
}

#[test]
fn all_zero_first_commit_marks_regions_committed() {
    let t = TempDir::new("zeros");
    let l = layout();
    let (mut store, _) = Store::open(t.path(), &l).unwrap();
    let z: Vec<Vec<u8>> = l.iter().map(|r| vec![0; r.len]).collect();
    let s = store.commit(&refs(&z)).unwrap();
    assert_eq!((s.chunks, s.generation), (0, 1));
    assert_eq!(s.bytes_written, frame_len(&[]));
    // Nothing changed and everything committed: no write at all.
    let s = store.commit(&refs(&z)).unwrap();
    assert_eq!((s.bytes_written, s.chunks, s.generation), (0, 0, 1));
    drop(store);
    let (_, got) = Store::open(t.path(), &l).unwrap();
    assert_eq!(got, some(&z));
}

#[test]
fn only_changed_chunks_are_written() {
    let t = TempDir::new("dirty");
    let l = vec![Region::new("latch", 4096), Region::new("zr", 1 << 20)];
    let (mut store, _) = Store::open(t.path(), &l).unwrap();
    let mut v: Vec<Vec<u8>> = l.iter().map(|r| vec![0; r.len]).collect();
    store.commit(&refs(&v)).unwrap();

    // Two words far apart: two records of one chunk each.
    v[0][10] = 1;
    v[1][700_001] = 2;
    let s = store.commit(&refs(&v)).unwrap();
    assert_eq!(s.chunks, 2);
    assert_eq!(s.bytes_written, frame_len(&[CHUNK, CHUNK]));

    // Two adjacent chunks share a record; the region's last chunk may be short.
    let l2 = vec![Region::new("r", 1000)];
    let t2 = TempDir::new("dirty2");
    let (mut s2, _) = Store::open(t2.path(), &l2).unwrap();
    let mut w = vec![0u8; 1000];
    s2.commit(&[&w]).unwrap();
    w[CHUNK - 1] = 1;
    w[CHUNK] = 1;
    w[999] = 1;
    let s = s2.commit(&[&w]).unwrap();
    assert_eq!(s.chunks, 3);
    assert_eq!(
        s.bytes_written,
        frame_len(&[2 * CHUNK, 1000 - 999 / CHUNK * CHUNK])
    );

    // Nothing changed: nothing written, same generation.
    let gen = store.generation();
    let s = store.commit(&refs(&v)).unwrap();
    assert_eq!((s.bytes_written, s.chunks, s.generation), (0, 0, gen));

    // A change and a change back within one scan is no change.
    v[1][5] = 9;
    v[1][5] = 0;
    assert_eq!(store.commit(&refs(&v)).unwrap().bytes_written, 0);

    drop(store);
    let (_, got) = Store::open(t.path(), &l).unwrap();
    assert_eq!(got, some(&v));
}

#[test]
fn layout_change_keeps_matching_regions_and_discards_resized() {
    let t = TempDir::new("layout");
    let l = layout();
    let (mut store, _) = Store::open(t.path(), &l).unwrap();
    let a = contents(&l, 3);
    store.commit(&refs(&a)).unwrap();
    drop(store);

    // Reordered, "history" resized, "clock" removed, "new" added.
    let l2 = vec![
        Region::new("zr", 64 * 1024),
        Region::new("new", 16),
        Region::new("history", 800),
        Region::new("latch:D", 2000),
    ];
    let (mut store, got) = Store::open(t.path(), &l2).unwrap();
    assert_eq!(got[0].as_deref(), Some(&a[1][..]));
    assert_eq!(got[1], None);
    assert_eq!(got[2], None);
    assert_eq!(got[3].as_deref(), Some(&a[0][..]));
    let w = store.warnings().join("\n");
    assert_eq!(store.warnings().len(), 2, "{w}");
    assert!(
        w.contains("\"history\": size changed from 700 to 800"),
        "{w}"
    );
    assert!(
        w.contains("\"clock\" (8 bytes) is no longer in the layout"),
        "{w}"
    );
    assert_eq!(store.committed(2), &[0u8; 800][..]);

    // The new layout is what the journal follows from now on.
    let mut b: Vec<Vec<u8>> = got
        .iter()
        .zip(&l2)
        .map(|(g, r)| g.clone().unwrap_or_else(|| vec![0; r.len]))
        .collect();
    b[2][799] = 5;
    store.commit(&refs(&b)).unwrap();
    drop(store);
    let (store, got) = Store::open(t.path(), &l2).unwrap();
    assert_eq!(got, some(&b));
    assert!(store.warnings().is_empty(), "{:?}", store.warnings());
}

#[test]
fn uncommitted_new_region_is_not_reported_as_resized() {
    let t = TempDir::new("newregion");
    let (store, _) = Store::open(t.path(), &[Region::new("a", 4)]).unwrap();
    drop(store);
    // "a" was never committed: resizing it is silent.
    let (store, got) = Store::open(t.path(), &[Region::new("a", 8)]).unwrap();
    assert_eq!(got, vec![None]);
    assert!(store.warnings().is_empty(), "{:?}", store.warnings());
}

/// Commits `states` one by one and returns the journal length after each commit.
fn commit_all(t: &TempDir, l: &[Region], states: &[Vec<Vec<u8>>]) -> Vec<u64> {
    let (mut store, _) = Store::open(t.path(), l).unwrap();
    states
        .iter()
        .map(|s| {
            store.commit(&refs(s)).unwrap();
            store.journal_len()
        })
        .collect()
}

#[test]
fn truncated_journal_tail_returns_previous_commit() {
    let t = TempDir::new("torn");
    let l = layout();
    let states = [contents(&l, 1), contents(&l, 2)];
    let ends = commit_all(&t, &l, &states);
    let f = OpenOptions::new().write(true).open(t.journal()).unwrap();
    f.set_len(ends[1] - 3).unwrap();
    drop(f);

    let (mut store, got) = Store::open(t.path(), &l).unwrap();
    assert_eq!(got, some(&states[0]));
    assert_eq!(store.generation(), 1);
    assert_eq!(store.warnings().len(), 1);
    assert!(
        store.warnings()[0].contains("torn frame"),
        "{:?}",
        store.warnings()
    );
    // The torn tail was cut, so later commits are not stranded behind it.
    assert_eq!(fs::metadata(t.journal()).unwrap().len(), ends[0]);
    let c = contents(&l, 3);
    assert_eq!(store.commit(&refs(&c)).unwrap().generation, 2);
    drop(store);
    let (store, got) = Store::open(t.path(), &l).unwrap();
    assert_eq!(got, some(&c));
    assert!(store.warnings().is_empty(), "{:?}", store.warnings());
}

#[test]
fn flipped_byte_in_last_frame_returns_previous_commit() {
    let t = TempDir::new("flip");
    let l = layout();
    let states = [contents(&l, 1), contents(&l, 2)];
    let ends = commit_all(&t, &l, &states);
    let mut j = fs::read(t.journal()).unwrap();
    let at = (ends[0] + (ends[1] - ends[0]) / 2) as usize;
    j[at] ^= 0x10;
    fs::write(t.journal(), &j).unwrap();

    let (store, got) = Store::open(t.path(), &l).unwrap();
    assert_eq!(got, some(&states[0]));
    assert!(
        store.warnings()[0].contains("checksum mismatch"),
        "{:?}",
        store.warnings()
    );
}

/// Exhaustive: cutting the journal at any byte, or flipping any byte, recovers
/// exactly the last commit whose frame is intact before that point.
#[test]
fn every_cut_and_every_flip_recovers_a_complete_commit() {
    let t = TempDir::new_fast("exhaustive");
    let l = vec![Region::new("a", 600), Region::new("b", 40)];
    let mut states = Vec::new();
    let mut cur: Vec<Vec<u8>> = l.iter().map(|r| vec![0; r.len]).collect();
    for k in 1..=5u8 {
        // Touch a different set of chunks each time, in both regions.
        cur[0][(k as usize * 97) % 600] = k;
        cur[0][599] = k;
        cur[1][k as usize] = k;
        states.push(cur.clone());
    }
    let ends = commit_all(&t, &l, &states);
    let journal = fs::read(t.journal()).unwrap();
    let image = fs::read(t.image()).unwrap();
    let expect = |limit: usize| -> (usize, Vec<Option<Vec<u8>>>) {
        let n = ends.iter().filter(|&&e| e as usize <= limit).count();
        let v = if n == 0 {
            vec![None, None]
        } else {
            some(&states[n - 1])
        };
        (n, v)
    };
    // A fresh directory per case: rewriting the same files in place makes ext4
    // flush them on close (auto_da_alloc), which is slow.
    let n = std::cell::Cell::new(0);
    let reset = |j: &[u8]| -> PathBuf {
        let dir = t.path().join(format!("case{}", n.get()));
        n.set(n.get() + 1);
        fs::create_dir(&dir).unwrap();
        fs::write(dir.join(IMAGE_FILE), &image).unwrap();
        fs::write(dir.join(JOURNAL_FILE), j).unwrap();
        dir
    };
    for cut in 0..=journal.len() {
        let dir = reset(&journal[..cut]);
        let (store, got) = Store::open(&dir, &l).unwrap();
        let (n, want) = expect(cut);
        assert_eq!(got, want, "cut at {cut}");
        assert_eq!(store.generation(), n as u64);
        assert_eq!(
            store.warnings().is_empty(),
            ends.contains(&(cut as u64)) || cut == 0
        );
    }
    for at in 0..journal.len() {
        let mut j = journal.clone();
        j[at] ^= 0x01;
        let dir = reset(&j);
        let (store, got) = Store::open(&dir, &l).unwrap();
        let (_, want) = expect(at);
        assert_eq!(got, want, "flip at {at}");
        assert_eq!(store.warnings().len(), 1, "flip at {at}");
    }
}

#[test]
fn checkpoint_then_more_commits_and_reopen() {
    let t = TempDir::new("checkpoint");
    let l = layout();
    let (mut store, _) = Store::open_with(
        t.path(),
        &l,
        StoreOptions {
            checkpoint_threshold: Some(150_000),
            ..StoreOptions::default()
        },
    )
    .unwrap();
    let mut last = Vec::new();
    let mut checkpoints = 0;
    for k in 1..=10u8 {
        last = contents(&l, k);
        let s = store.commit(&refs(&last)).unwrap();
        assert_eq!(s.generation, k as u64);
        if s.checkpointed {
            checkpoints += 1;
            assert_eq!(store.journal_len(), 0);
        }
    }
    assert!(checkpoints >= 2, "{checkpoints} checkpoints");
    assert!(store.journal_len() > 0, "commits after the last checkpoint");
    drop(store);
    let (mut store, got) = Store::open(t.path(), &l).unwrap();
    assert_eq!(got, some(&last));
    assert_eq!(store.generation(), 10);
    assert!(store.warnings().is_empty(), "{:?}", store.warnings());

    // Explicit checkpoint, reopen from the image alone.
    store.checkpoint().unwrap();
    assert_eq!(fs::metadata(t.journal()).unwrap().len(), 0);
    drop(store);
    let (_, got) = Store::open(t.path(), &l).unwrap();
    assert_eq!(got, some(&last));
}

#[test]
fn crash_between_rename_and_journal_truncation() {
    let t = TempDir::new("ckptcrash");
    let l = layout();
    let (mut store, _) = Store::open(t.path(), &l).unwrap();
    let a = contents(&l, 1);
    let b = contents(&l, 2);
    store.commit(&refs(&a)).unwrap();
    store.commit(&refs(&b)).unwrap();
    let journal = fs::read(t.journal()).unwrap();
    store.checkpoint().unwrap();
    drop(store);
    // As if the process died after the rename: new image, old journal.
    fs::write(t.journal(), &journal).unwrap();
    let (mut store, got) = Store::open(t.path(), &l).unwrap();
    assert_eq!(got, some(&b));
    assert_eq!(store.generation(), 2);
    assert!(store.warnings().is_empty(), "{:?}", store.warnings());
    assert_eq!(store.journal_len(), 0, "stale frames are dropped");
    let c = contents(&l, 3);
    store.commit(&refs(&c)).unwrap();
    drop(store);
    let (_, got) = Store::open(t.path(), &l).unwrap();
    assert_eq!(got, some(&c));
}

#[test]
fn crash_during_layout_checkpoint_with_old_frames() {
    // The layout-change checkpoint died before truncating: the old journal's frames
    // name regions of the old layout but are all ≤ the image generation.
    let t = TempDir::new("layoutcrash");
    let l = layout();
    let (mut store, _) = Store::open(t.path(), &l).unwrap();
    let a = contents(&l, 1);
    store.commit(&refs(&a)).unwrap();
    drop(store);
    let journal = fs::read(t.journal()).unwrap();
    let l2 = vec![Region::new("zr", 64 * 1024)];
    drop(Store::open(t.path(), &l2).unwrap());
    fs::write(t.journal(), &journal).unwrap();
    let (store, got) = Store::open(t.path(), &l2).unwrap();
    assert_eq!(got, vec![Some(a[1].clone())]);
    assert!(store.warnings().is_empty(), "{:?}", store.warnings());
}

#[test]
fn stale_temp_image_is_ignored_and_removed() {
    let t = TempDir::new("tmp");
    let l = layout();
    let a = contents(&l, 1);
    commit_all(&t, &l, std::slice::from_ref(&a));
    fs::write(t.path().join(IMAGE_TMP), b"half a checkpoint").unwrap();
    let (store, got) = Store::open(t.path(), &l).unwrap();
    assert_eq!(got, some(&a));
    assert!(store.warnings().is_empty());
    assert!(!t.path().join(IMAGE_TMP).exists());
}

#[test]
fn damaged_region_loses_only_itself_and_is_reported() {
    let t = TempDir::new("badimage");
    let l = layout();
    let a = contents(&l, 1);
    commit_all(&t, &l, std::slice::from_ref(&a));
    drop(Store::open(t.path(), &l).unwrap()); // clean open: nothing lost
    let (mut store, _) = Store::open(t.path(), &l).unwrap();
    store.checkpoint().unwrap(); // everything in the image, journal empty
    drop(store);
    // Flip one byte in the middle of the image: inside "zr" (64 KiB).
    let mut img = fs::read(t.image()).unwrap();
    let mid = img.len() / 2;
    img[mid] ^= 0xff;
    fs::write(t.image(), &img).unwrap();

    let (mut store, got) = Store::open(t.path(), &l).unwrap();
    assert_eq!(got[0], Some(a[0].clone()), "other regions intact");
    assert_eq!(got[1], None, "the damaged region is lost");
    assert_eq!(got[2], Some(a[2].clone()));
    assert_eq!(got[3], Some(a[3].clone()));
    assert_eq!(store.lost().len(), 1, "{:?}", store.lost());
    assert!(store.lost()[0].contains("\"zr\""), "{:?}", store.lost());
    let w = store.warnings().join("\n");
    assert!(w.contains("region \"zr\": checksum mismatch"), "{w}");
    assert!(t.path().join("image.bin.corrupt").exists());
    // Usable again, and the loss is reported once.
    store.commit(&refs(&a)).unwrap();
    drop(store);
    let (store, got) = Store::open(t.path(), &l).unwrap();
    assert_eq!(got, some(&a));
    assert!(store.warnings().is_empty());
    assert!(store.lost().is_empty());
}

#[test]
fn damaged_image_header_loses_everything_and_is_reported() {
    let t = TempDir::new("badheader");
    let l = layout();
    let a = contents(&l, 1);
    commit_all(&t, &l, std::slice::from_ref(&a));
    let mut img = fs::read(t.image()).unwrap();
    img[20] ^= 0xff; // in the region table
    fs::write(t.image(), &img).unwrap();
    let (store, got) = Store::open(t.path(), &l).unwrap();
    assert_eq!(got, vec![None; 4]);
    let w = store.warnings().join("\n");
    assert!(w.contains("image.bin: corrupt"), "{w}");
    assert!(w.contains("journal without a valid image"), "{w}");
    assert_eq!(store.lost().len(), 1);
    assert!(t.path().join("image.bin.corrupt").exists());
    assert!(t.path().join("journal.log.corrupt").exists());
}

#[test]
fn torn_tail_is_not_a_loss_but_a_bad_frame_is() {
    let t = TempDir::new("tornloss");
    let l = vec![Region::new("a", 16)];
    commit_all(&t, &l, &[vec![vec![1u8; 16]], vec![vec![2u8; 16]]]);
    let j = fs::read(t.journal()).unwrap();
    fs::write(t.journal(), &j[..j.len() - 3]).unwrap();
    let (store, _) = Store::open(t.path(), &l).unwrap();
    assert!(!store.warnings().is_empty());
    assert!(store.lost().is_empty(), "{:?}", store.lost());
    drop(store);
    commit_all(&t, &l, &[vec![vec![3u8; 16]]]);
    let mut j = fs::read(t.journal()).unwrap();
    let n = j.len();
    j[n - 6] ^= 1; // inside the last, complete frame
    fs::write(t.journal(), &j).unwrap();
    let (store, _) = Store::open(t.path(), &l).unwrap();
    assert_eq!(store.lost().len(), 1, "{:?}", store.lost());
}

#[test]
fn truncated_or_garbage_image_does_not_panic() {
    let t = TempDir::new("garbage");
    let l = layout();
    commit_all(&t, &l, &[contents(&l, 1)]);
    let img = fs::read(t.image()).unwrap();
    let journal = fs::read(t.journal()).unwrap();
    for len in [0, 5, 20, 40, img.len() - 1] {
        fs::write(t.image(), &img[..len]).unwrap();
        fs::write(t.journal(), &journal).unwrap();
        let (store, got) = Store::open(t.path(), &l).unwrap();
        if len < 40 {
            assert_eq!(got, vec![None; 4]);
        } else {
            // Cut inside the last region: only that one is lost.
            assert_eq!(got[3], None);
        }
        assert!(!store.warnings().is_empty());
        assert!(!store.lost().is_empty());
    }
    // Valid CRC over nonsense: a region table that overruns the file.
    let bad = image_header(7, [("x", 1usize << 40, true, 0)].into_iter());
    fs::write(t.image(), &bad).unwrap();
    let (store, _) = Store::open(t.path(), &l).unwrap();
    assert!(
        store.warnings()[0].contains("region table announces"),
        "{:?}",
        store.warnings()
    );
}

#[test]
fn generation_gap_and_garbage_tail_stop_replay() {
    let t = TempDir::new("gap");
    let l = vec![Region::new("a", 16)];
    let s1 = vec![vec![1u8; 16]];
    let ends = commit_all(&t, &l, std::slice::from_ref(&s1));
    // A valid frame with generation 3 after generation 1.
    let mut f = Vec::new();
    begin_frame(&mut f, 3);
    push_record(&mut f, 0, 0, &[9; 16]);
    finish_frame(&mut f, 1);
    let mut j = fs::read(t.journal()).unwrap();
    j.extend_from_slice(&f);
    fs::write(t.journal(), &j).unwrap();
    let (store, got) = Store::open(t.path(), &l).unwrap();
    assert_eq!(got, some(&s1));
    assert!(store.warnings()[0].contains("generation 3 follows generation 1"));
    drop(store);
    assert_eq!(fs::metadata(t.journal()).unwrap().len(), ends[0]);

    // A valid frame whose record lies outside the region.
    let mut f = Vec::new();
    begin_frame(&mut f, 2);
    push_record(&mut f, 0, 10, &[9; 16]);
    finish_frame(&mut f, 1);
    let mut j = fs::read(t.journal()).unwrap();
    j.extend_from_slice(&f);
    j.extend_from_slice(b"trailing garbage");
    fs::write(t.journal(), &j).unwrap();
    let (store, got) = Store::open(t.path(), &l).unwrap();
    assert_eq!(got, some(&s1));
    assert!(
        store.warnings()[0].contains("outside the layout"),
        "{:?}",
        store.warnings()
    );
}

#[test]
fn commit_checks_the_layout() {
    let t = TempDir::new("check");
    let (mut store, _) = Store::open(t.path(), &[Region::new("a", 4)]).unwrap();
    assert!(matches!(store.commit(&[]), Err(PersistError::Layout(_))));
    let e = store.commit(&[&[0; 5]]).unwrap_err();
    assert_eq!(
        e.to_string(),
        "persist layout: region \"a\": commit of 5 bytes, layout has 4"
    );
    let dup = [Region::new("a", 1), Region::new("a", 2)];
    assert!(matches!(
        Store::open(t.path(), &dup),
        Err(PersistError::Layout(_))
    ));
    assert!(matches!(
        Store::open(t.path(), &[Region::new("", 1)]),
        Err(PersistError::Layout(_))
    ));
}

#[test]
fn io_errors_name_the_path() {
    let t = TempDir::new("ioerr");
    fs::create_dir_all(t.path()).unwrap();
    let file = t.path().join("not-a-dir");
    fs::write(&file, b"").unwrap();
    let e = Store::open(&file, &layout()).unwrap_err();
    assert!(matches!(e, PersistError::Io { .. }));
    assert!(e.to_string().contains("not-a-dir"), "{e}");
}

#[test]
fn sync_mode_and_empty_regions() {
    let t = TempDir::new("sync");
    let l = vec![Region::new("empty", 0), Region::new("a", 3)];
    let (mut store, got) = Store::open_with(
        t.path(),
        &l,
        StoreOptions {
            sync: true,
            checkpoint_threshold: Some(1),
        },
    )
    .unwrap();
    assert_eq!(got, vec![None, None]);
    let s = store.commit(&[&[], &[1, 2, 3]]).unwrap();
    assert!(s.checkpointed);
    store.set_sync(false);
    store.set_checkpoint_threshold(1 << 20);
    let s = store.commit(&[&[], &[1, 2, 4]]).unwrap();
    assert!(!s.checkpointed);
    drop(store);
    let (_, got) = Store::open(t.path(), &l).unwrap();
    assert_eq!(got, vec![Some(vec![]), Some(vec![1, 2, 4])]);
}
