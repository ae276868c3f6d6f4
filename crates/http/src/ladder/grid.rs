//! A rung on a grid: contacts in columns `0..cols`, every output in column
//! `cols` (the right side), one row per parallel branch or output.

use super::build::{Fan, Item, Net, Rung, RungBody};
use super::Elem;

/// What a cell holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cell<'a> {
    Elem(&'a Elem),
    /// A horizontal wire through the cell.
    Wire,
}

/// A laid-out rung.
#[derive(Debug, Default)]
pub struct Grid<'a> {
    /// Contact columns; outputs are in column `cols`.
    pub cols: usize,
    pub rows: usize,
    /// (row, column, cell).
    pub cells: Vec<(usize, usize, Cell<'a>)>,
    /// Vertical links at the left edge of a column: (column, top row, bottom row).
    pub links: Vec<(usize, usize, usize)>,
    /// A standalone instruction (END, FEND, MCR …) across the rung.
    pub standalone: Option<&'a Elem>,
    /// The rung laid out.
    pub rung: Option<&'a Rung>,
}

fn size(n: &Net) -> (usize, usize) {
    match n {
        Net::Elem(_) => (1, 1),
        Net::Series(v) => v
            .iter()
            .map(size)
            .fold((0, 1), |(w, h), (a, b)| (w + a, h.max(b))),
        Net::Parallel(v) => v
            .iter()
            .map(size)
            .fold((1, 0), |(w, h), (a, b)| (w.max(a), h + b)),
    }
}

fn prefix_size(f: &Fan) -> (usize, usize) {
    f.prefix.as_ref().map_or((0, 1), size)
}

fn fan_width(f: &Fan) -> usize {
    prefix_size(f).0
        + f.items
            .iter()
            .map(|i| match i {
                Item::Out(_) => 0,
                Item::Fan(c) => fan_width(c),
            })
            .max()
            .unwrap_or(0)
}

fn fan_height(f: &Fan) -> usize {
    let items: usize = f
        .items
        .iter()
        .map(|i| match i {
            Item::Out(_) => 1,
            Item::Fan(c) => fan_height(c),
        })
        .sum();
    prefix_size(f).1.max(items).max(1)
}

impl<'a> Grid<'a> {
    /// Lays out `rung`.
    pub fn of(rung: &'a Rung) -> Grid<'a> {
        match &rung.body {
            RungBody::Standalone(e) => Grid {
                cols: 1,
                rows: 1,
                standalone: Some(e),
                ..Grid::default()
            },
            RungBody::Fan(f) => {
                let mut g = Grid {
                    cols: fan_width(f).max(1),
                    rows: fan_height(f),
                    rung: Some(rung),
                    ..Grid::default()
                };
                g.fan(f, 0, 0);
                g.cells.sort_by_key(|(r, c, _)| (*r, *c));
                g
            }
        }
    }

    fn wires(&mut self, row: usize, from: usize, to: usize) {
        for c in from..to {
            self.cells.push((row, c, Cell::Wire));
        }
    }

    fn net(&mut self, n: &'a Net, row: usize, col: usize) {
        match n {
            Net::Elem(e) => self.cells.push((row, col, Cell::Elem(e))),
            Net::Series(v) => {
                let mut c = col;
                for p in v {
                    self.net(p, row, c);
                    c += size(p).0;
                }
            }
            Net::Parallel(v) => {
                let w = size(n).0;
                let mut r = row;
                let mut last = row;
                for p in v {
                    let (pw, ph) = size(p);
                    self.net(p, r, col);
                    self.wires(r, col + pw, col + w);
                    last = r;
                    r += ph;
                }
                if last > row {
                    self.links.push((col, row, last));
                    self.links.push((col + w, row, last));
                }
            }
        }
    }

    fn fan(&mut self, f: &'a Fan, row: usize, col: usize) {
        if let Some(p) = &f.prefix {
            self.net(p, row, col);
        }
        let c2 = col + prefix_size(f).0;
        let mut r = row;
        let mut last = row;
        for i in &f.items {
            last = r;
            match i {
                Item::Out(e) => {
                    self.wires(r, c2, self.cols);
                    self.cells.push((r, self.cols, Cell::Elem(e)));
                    r += 1;
                }
                Item::Fan(c) => {
                    self.fan(c, r, c2);
                    r += fan_height(c);
                }
            }
        }
        if last > row {
            self.links.push((c2, row, last));
        }
    }
}
