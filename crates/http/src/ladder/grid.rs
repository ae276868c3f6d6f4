//! A rung on a grid: contacts in columns `0..cols`, every output in column
//! `cols` (the right side), one row per parallel branch or output.

use super::build::{Fan, Item, Net, Rung, RungBody};
use super::Elem;

/// What a cell holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cell<'a> {
    Elem(&'a Elem),
    /// A horizontal wire through the cell, with where its power comes from.
    Wire(Feed<'a>),
}

/// Where the power on a wire comes from, for the page's power flow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Feed<'a> {
    /// What flows into element `id` (the wire leading to an output, the left
    /// side of a parallel block).
    Into(u32),
    /// What flows out of a net (the wire after a short parallel branch, the
    /// right side of a parallel block): the OR of its [`terminals`].
    After(&'a Net),
}

/// The elements whose outputs make a net's output: a series ends with its
/// last part, a parallel block is the OR of its branches.
pub fn terminals(n: &Net) -> Vec<u32> {
    match n {
        Net::Elem(e) => vec![e.id],
        Net::Series(v) => v.last().map_or_else(Vec::new, terminals),
        Net::Parallel(v) => v.iter().flat_map(terminals).collect(),
    }
}

/// The first element power reaches in a net.
fn first(n: &Net) -> Option<u32> {
    match n {
        Net::Elem(e) => Some(e.id),
        Net::Series(v) | Net::Parallel(v) => v.first().and_then(first),
    }
}

fn first_of_item(i: &Item) -> Option<u32> {
    match i {
        Item::Out(e) => Some(e.id),
        Item::Fan(f) => f
            .prefix
            .as_ref()
            .and_then(first)
            .or_else(|| f.items.first().and_then(first_of_item)),
    }
}

/// A vertical link at the left edge of a column.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Link<'a> {
    pub col: usize,
    pub top: usize,
    pub bottom: usize,
    pub feed: Option<Feed<'a>>,
}

/// A laid-out rung.
#[derive(Debug, Default)]
pub struct Grid<'a> {
    /// Contact columns; outputs are in column `cols`.
    pub cols: usize,
    pub rows: usize,
    /// (row, column, cell).
    pub cells: Vec<(usize, usize, Cell<'a>)>,
    /// Vertical links at the left edge of a column.
    pub links: Vec<Link<'a>>,
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

    fn wires(&mut self, row: usize, from: usize, to: usize, feed: Feed<'a>) {
        for c in from..to {
            self.cells.push((row, c, Cell::Wire(feed)));
        }
    }

    fn link(&mut self, col: usize, top: usize, bottom: usize, feed: Option<Feed<'a>>) {
        self.links.push(Link {
            col,
            top,
            bottom,
            feed,
        });
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
                    self.wires(r, col + pw, col + w, Feed::After(p));
                    last = r;
                    r += ph;
                }
                if last > row {
                    self.link(col, row, last, first(n).map(Feed::Into));
                    self.link(col + w, row, last, Some(Feed::After(n)));
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
                    self.wires(r, c2, self.cols, Feed::Into(e.id));
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
            let feed = f.items.first().and_then(first_of_item).map(Feed::Into);
            self.link(c2, row, last, feed);
        }
    }
}
