//! Declared memory layouts: named, typed fields over a block of device words
//! (a PID loop's I/O data, process-control loop memory). One declaration serves
//! the instruction code (typed accessors), and the monitor, OPC UA and the
//! documentation ([`Field`] lists), so they all read the same definition.
//!
//! ```
//! softplc_ir::layout! {
//!     /// Two fields over a 4-word block.
//!     pub struct Example[4] {
//!         /// The set value.
//!         sv: i16 @ 0,
//!         /// A real number in two words, low word first.
//!         gain: f32 @ 2,
//!     }
//! }
//! let mut w = [0u16; 4];
//! Example::gain.set(&mut w, 1.5);
//! assert_eq!(Example::gain.get(&w), 1.5);
//! assert_eq!(Example::FIELDS[1].offset, 2);
//! ```
//!
//! 32- and 64-bit fields are stored low word first (MELSEC 32-bit data, 004
//! §2.8). A dialect with another word order declares its own field types.

use std::marker::PhantomData;

/// The value type of a field.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FieldType {
    U16,
    I16,
    U32,
    I32,
    F32,
    U64,
    F64,
}

impl FieldType {
    /// Words the field occupies.
    pub const fn words(self) -> usize {
        match self {
            FieldType::U16 | FieldType::I16 => 1,
            FieldType::U32 | FieldType::I32 | FieldType::F32 => 2,
            FieldType::U64 | FieldType::F64 => 4,
        }
    }
}

/// One field of a layout, for monitors and generated documentation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Field {
    pub name: &'static str,
    /// Word offset from the start of the block.
    pub offset: usize,
    pub ty: FieldType,
    pub doc: &'static str,
}

/// A value stored in device words, low word first.
pub trait WordValue: Copy {
    const TYPE: FieldType;
    fn read(w: &[u16]) -> Self;
    fn write(self, w: &mut [u16]);
}

fn get32(w: &[u16]) -> u32 {
    w[0] as u32 | (w[1] as u32) << 16
}

fn put32(w: &mut [u16], v: u32) {
    w[0] = v as u16;
    w[1] = (v >> 16) as u16;
}

fn get64(w: &[u16]) -> u64 {
    get32(w) as u64 | (get32(&w[2..]) as u64) << 32
}

fn put64(w: &mut [u16], v: u64) {
    put32(w, v as u32);
    put32(&mut w[2..], (v >> 32) as u32);
}

macro_rules! word_value {
    ($t:ty, $ft:ident, |$r:ident| $read:expr, |$s:ident, $v:ident| $write:expr) => {
        impl WordValue for $t {
            const TYPE: FieldType = FieldType::$ft;
            #[inline]
            fn read($r: &[u16]) -> Self {
                $read
            }
            #[inline]
            fn write(self, $s: &mut [u16]) {
                let $v = self;
                $write
            }
        }
    };
}

word_value!(u16, U16, |w| w[0], |w, v| w[0] = v);
word_value!(i16, I16, |w| w[0] as i16, |w, v| w[0] = v as u16);
word_value!(u32, U32, |w| get32(w), |w, v| put32(w, v));
word_value!(i32, I32, |w| get32(w) as i32, |w, v| put32(w, v as u32));
word_value!(f32, F32, |w| f32::from_bits(get32(w)), |w, v| put32(
    w,
    v.to_bits()
));
word_value!(u64, U64, |w| get64(w), |w, v| put64(w, v));
word_value!(f64, F64, |w| f64::from_bits(get64(w)), |w, v| put64(
    w,
    v.to_bits()
));

/// A typed field at a word offset of a block (made by [`layout!`](crate::layout)).
#[derive(Clone, Copy, Debug)]
pub struct At<T> {
    offset: usize,
    _t: PhantomData<fn() -> T>,
}

impl<T: WordValue> At<T> {
    pub const fn new(offset: usize) -> Self {
        At {
            offset,
            _t: PhantomData,
        }
    }

    pub const fn offset(self) -> usize {
        self.offset
    }

    /// The `k`-th of a run of fields of this type that begins with this one
    /// (a table a layout declares by its first element, e.g. the n inputs of
    /// an instruction whose count is data): element 0 is the field itself.
    #[inline]
    pub fn nth(self, k: usize) -> Self {
        At::new(self.offset + k * T::TYPE.words())
    }

    /// The field's value in block `w` (which starts at the layout's word 0).
    #[inline]
    pub fn get(self, w: &[u16]) -> T {
        T::read(&w[self.offset..])
    }

    #[inline]
    pub fn set(self, w: &mut [u16], v: T) {
        v.write(&mut w[self.offset..])
    }
}

/// Declares a layout: `pub struct Name[WORDS] { /// doc \n field: type @ offset, … }`
/// gives `Name::field` (an [`At`] with `get`/`set`), `Name::WORDS` and
/// `Name::FIELDS`. Every field must lie within the block (checked at compile time).
#[macro_export]
macro_rules! layout {
    ($(#[$m:meta])* $vis:vis struct $name:ident[$words:expr] {
        $($(#[doc = $doc:literal])* $field:ident : $ty:ident @ $off:literal),* $(,)?
    }) => {
        $(#[$m])*
        #[derive(Clone, Copy, Debug)]
        $vis struct $name;

        #[allow(non_upper_case_globals, dead_code, clippy::int_plus_one)]
        impl $name {
            /// Words of the block.
            pub const WORDS: usize = $words;
            $(
                $(#[doc = $doc])*
                pub const $field: $crate::layout::At<$ty> = {
                    assert!(
                        $off + <$ty as $crate::layout::WordValue>::TYPE.words() <= $words,
                        concat!("field `", stringify!($field), "` lies outside its layout")
                    );
                    $crate::layout::At::new($off)
                };
            )*
            /// The fields, in declaration order.
            pub const FIELDS: &'static [$crate::layout::Field] = &[$(
                $crate::layout::Field {
                    name: stringify!($field),
                    offset: $off,
                    ty: <$ty as $crate::layout::WordValue>::TYPE,
                    doc: concat!($($doc),*),
                }
            ),*];
        }
    };
}
