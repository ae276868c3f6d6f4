//! Dialect settings: typed values a project chooses (plc.toml) that
//! instructions read when they compile, so a choice costs nothing in the scan.
//! The language front end knows none of them; a dialect crate defines the
//! types (e.g. the process-CPU decisions of `softplc_melsec::process`) and an
//! instruction asks for one with `Args::setting`.

use std::any::Any;
use std::sync::Arc;

/// A set of settings, at most one value per type.
#[derive(Clone, Default)]
pub struct Settings(Vec<Arc<dyn Any + Send + Sync>>);

impl Settings {
    pub fn new() -> Settings {
        Settings::default()
    }

    /// The settings with `value` set (replacing one of the same type).
    pub fn with<T: Any + Send + Sync>(mut self, value: T) -> Settings {
        self.0.retain(|v| !v.is::<T>());
        self.0.push(Arc::new(value));
        self
    }

    /// The value of type `T`, if set.
    pub fn get<T: Any>(&self) -> Option<&T> {
        self.0.iter().find_map(|v| v.downcast_ref::<T>())
    }
}

impl std::fmt::Debug for Settings {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Settings({} values)", self.0.len())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Clone, Debug, Default, PartialEq)]
    struct Gain(f32);

    #[test]
    fn a_value_per_type_replaced_by_with() {
        let s = Settings::new().with(Gain(1.0)).with(7u8).with(Gain(2.0));
        assert_eq!(s.get::<Gain>(), Some(&Gain(2.0)));
        assert_eq!(s.get::<u8>(), Some(&7));
        assert_eq!(s.get::<u16>(), None);
    }
}
