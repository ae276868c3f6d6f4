use super::*;
use crate::device::{DeviceConfig, DeviceKind, DeviceMemory};

fn mem() -> DeviceMemory {
    DeviceMemory::new(&DeviceConfig::default())
}

fn word(m: &DeviceMemory, k: DeviceKind, n: i64) -> u16 {
    m.get_word(k, n).unwrap()
}

#[test]
fn round_trips() {
    let mut mem = mem();
    let w =
        |m: &mut DeviceMemory, d: &str, v: &str| DeviceSpec::parse(d).unwrap().write(m, v).unwrap();
    let r = |m: &DeviceMemory, d: &str| DeviceSpec::parse(d).unwrap().read(m).unwrap();
    w(&mut mem, "D0", "-5");
    assert_eq!(r(&mem, "D0"), Value::Int(-5));
    assert_eq!(r(&mem, "D0:u16"), Value::Int(65531));
    w(&mut mem, "D10:f32", "1.5");
    assert_eq!(mem.get_word(DeviceKind::D, 11).unwrap(), 0x3FC0);
    assert_eq!(r(&mem, "D10:f32"), Value::Float(1.5));
    w(&mut mem, "D20:i32", "H12345678");
    assert_eq!(mem.get_word(DeviceKind::D, 20).unwrap(), 0x5678);
    assert_eq!(r(&mem, "D20:u32"), Value::Int(0x1234_5678));
    w(&mut mem, "K2Y10", "0xA5");
    assert_eq!(r(&mem, "Y10"), Value::Bool(true));
    assert_eq!(r(&mem, "Y11"), Value::Bool(false));
    assert_eq!(r(&mem, "Y17"), Value::Bool(true));
    assert_eq!(r(&mem, "K2Y10"), Value::Int(0xA5));
    w(&mut mem, "D30:str", "ABC");
    assert_eq!(mem.get_word(DeviceKind::D, 30).unwrap(), 0x4241);
    assert_eq!(mem.get_word(DeviceKind::D, 31).unwrap(), 0x0043);
    assert_eq!(r(&mem, "D30:str"), Value::Str("ABC".into()));
    w(&mut mem, "D0.F", "1");
    assert_eq!(r(&mem, "D0.F"), Value::Bool(true));
    w(&mut mem, "Z0", "3");
    w(&mut mem, "D200Z0", "77");
    assert_eq!(mem.get_word(DeviceKind::D, 203).unwrap(), 77);
    assert!(DeviceSpec::parse("D0:f64").is_err());
    assert!(DeviceSpec::parse("D0")
        .unwrap()
        .write(&mut mem, "70000")
        .is_err());
    assert!(DeviceSpec::parse("D99999").unwrap().read(&mem).is_err());
}

#[test]
fn typed_writes_put_exact_bits_low_word_first() {
    let mut m = mem();
    let put = |m: &mut DeviceMemory, d: &str, v: Value| {
        DeviceSpec::parse(d).unwrap().write_value(m, &v).unwrap()
    };
    put(&mut m, "D0", Value::Int(-2));
    assert_eq!(word(&m, DeviceKind::D, 0), 0xFFFE);
    put(&mut m, "D1:u16", Value::Int(0xBEEF));
    assert_eq!(word(&m, DeviceKind::D, 1), 0xBEEF);
    put(&mut m, "D2:i32", Value::Int(-0x1234_5679));
    // -0x12345679 = 0xEDCBA987: low word first.
    assert_eq!(word(&m, DeviceKind::D, 2), 0xA987);
    assert_eq!(word(&m, DeviceKind::D, 3), 0xEDCB);
    put(&mut m, "D4:u32", Value::Int(0xDEAD_BEEF));
    assert_eq!(word(&m, DeviceKind::D, 4), 0xBEEF);
    assert_eq!(word(&m, DeviceKind::D, 5), 0xDEAD);
    put(&mut m, "D6:f32", Value::Float(-2.5));
    // -2.5f32 = 0xC0200000.
    assert_eq!(word(&m, DeviceKind::D, 6), 0x0000);
    assert_eq!(word(&m, DeviceKind::D, 7), 0xC020);
    put(&mut m, "D8:f32", Value::Int(3));
    assert_eq!(word(&m, DeviceKind::D, 9), 0x4040);
    put(&mut m, "D10:str", Value::Str("ABCD".into()));
    assert_eq!(word(&m, DeviceKind::D, 10), 0x4241);
    assert_eq!(word(&m, DeviceKind::D, 11), 0x4443);
    assert_eq!(word(&m, DeviceKind::D, 12), 0x0000);
    put(&mut m, "M5", Value::Bool(true));
    assert_eq!(m.get_bit(DeviceKind::M, 5), Ok(true));
    put(&mut m, "D20.3", Value::Bool(true));
    assert_eq!(word(&m, DeviceKind::D, 20), 0x0008);
    put(&mut m, "D20.3", Value::Int(0));
    assert_eq!(word(&m, DeviceKind::D, 20), 0x0000);
    put(&mut m, "K1M8", Value::Int(0b1010));
    assert_eq!(m.get_bit(DeviceKind::M, 8), Ok(false));
    assert_eq!(m.get_bit(DeviceKind::M, 9), Ok(true));
    assert_eq!(m.get_bit(DeviceKind::M, 11), Ok(true));
    // The same value written as text gives the same bits.
    let mut t = mem();
    for (d, v) in [
        ("D0", "-2"),
        ("D1:u16", "HBEEF"),
        ("D2:i32", "-305419897"),
        ("D4:u32", "0xDEADBEEF"),
        ("D6:f32", "-2.5"),
        ("D8:f32", "3"),
        ("D10:str", "ABCD"),
        ("M5", "on"),
        ("K1M8", "10"),
    ] {
        DeviceSpec::parse(d).unwrap().write(&mut t, v).unwrap();
    }
    assert_eq!(&t.words[..13], &m.words[..13]);
    assert_eq!(&t.bits[..], &m.bits[..]);
}

#[test]
fn typed_write_errors_name_the_device_and_write_nothing() {
    let mut m = mem();
    let spec = DeviceSpec::parse("D0").unwrap();
    let e = spec.write_value(&mut m, &Value::Int(70000)).unwrap_err();
    assert_eq!(e.to_string(), "`D0`: `70000` is not a valid I16 value");
    let e = spec.write_value(&mut m, &Value::Float(1.0)).unwrap_err();
    assert!(matches!(e, AccessError::Value { ref device, .. } if device == "D0"));
    let e = DeviceSpec::parse("M0")
        .unwrap()
        .write_value(&mut m, &Value::Int(2))
        .unwrap_err();
    assert!(e.to_string().starts_with("`M0`:"), "{e}");
    let e = DeviceSpec::parse("D12287:i32")
        .unwrap()
        .write_value(&mut m, &Value::Int(1))
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "`D12287:i32`: D12288 is outside the configured range (12288 points)"
    );
    assert_eq!(word(&m, DeviceKind::D, 12287), 0);
    // Text and value writes report the same way.
    let e = DeviceSpec::parse("D0").unwrap().write(&mut m, "H10000");
    assert_eq!(e.unwrap_err(), "`D0`: `H10000` is not a valid I16 value");
}

#[test]
fn r_addresses_the_block_sd648_selects() {
    assert_eq!(r_to_zr(0, 5), 5);
    assert_eq!(r_to_zr(1, 0), 32768);
    assert_eq!(r_to_zr(3, 100), 98404);
    let mut m = mem();
    // The selector word is the dialect's (MELSEC's SD648).
    let sd648 = m.map.index(DeviceKind::SD, 648);
    m.map.set_r_block(sd648);
    m.set_word(DeviceKind::SD, 648, 1).unwrap();
    assert_eq!(selected_block(&m), 1);
    // MC protocol: R0 with SD648 = 1 is ZR32768.
    let s = m.span(DeviceKind::R, 0, 2, RBlock::Selected).unwrap();
    m.write_span_words(&s, &[0x1111, 0x2222]).unwrap();
    assert_eq!(word(&m, DeviceKind::ZR, 32768), 0x1111);
    assert_eq!(word(&m, DeviceKind::ZR, 32769), 0x2222);
    assert_eq!(word(&m, DeviceKind::ZR, 0), 0);
    assert_eq!(m.read_span_words(&s).unwrap(), vec![0x1111, 0x2222]);
    // Names (CLI, scenarios) keep the documented window: R0 is ZR0.
    DeviceSpec::parse("R0").unwrap().write(&mut m, "7").unwrap();
    assert_eq!(word(&m, DeviceKind::ZR, 0), 7);
    let first = m.span(DeviceKind::R, 0, 1, RBlock::First).unwrap();
    assert_eq!(m.read_span_words(&first).unwrap(), vec![7]);
    // A block past the last ZR point is out of range, naming R and the ZR point.
    m.set_word(DeviceKind::SD, 648, 15).unwrap(); // R25590 of block 15 is ZR517110
    let e = m
        .span(DeviceKind::R, 25590, 16, RBlock::Selected)
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "`R25590-R25605`: ZR517120 is outside the configured range (517120 points)"
    );
    assert!(m.span(DeviceKind::R, 25590, 10, RBlock::Selected).is_ok());
    // R itself stops at R32767 in every block.
    let e = m.span(DeviceKind::R, 32767, 2, RBlock::First).unwrap_err();
    assert!(e.to_string().starts_with("`R32767-R32768`: R32768"), "{e}");
}

#[test]
fn spans_read_and_write_words_and_bits() {
    let mut m = mem();
    let x = m.span(DeviceKind::X, 0x10, 32, RBlock::First).unwrap();
    assert!(x.is_bit());
    assert_eq!((x.kind(), x.number(), x.len()), (DeviceKind::X, 0x10, 32));
    m.write_span_words(&x, &[0x8001, 0x0002]).unwrap();
    assert_eq!(m.get_bit(DeviceKind::X, 0x10), Ok(true));
    assert_eq!(m.get_bit(DeviceKind::X, 0x1F), Ok(true));
    assert_eq!(m.get_bit(DeviceKind::X, 0x21), Ok(true));
    assert_eq!(m.read_span_words(&x).unwrap(), vec![0x8001, 0x0002]);
    let b = m.read_span_bits(&x).unwrap();
    assert_eq!(b.iter().filter(|b| **b).count(), 3);
    let y = m.span(DeviceKind::Y, 0, 3, RBlock::First).unwrap();
    m.write_span_bits(&y, &[true, false, true]).unwrap();
    assert_eq!(m.read_span_words(&y).unwrap(), vec![0b101]);
    let d = m.span(DeviceKind::D, 100, 2, RBlock::First).unwrap();
    m.write_span_words(&d, &[1, 2]).unwrap();
    assert_eq!(m.read_span_words(&d).unwrap(), vec![1, 2]);
    // Errors name the span.
    let e = m.read_span_bits(&d).unwrap_err();
    assert_eq!(
        e.to_string(),
        "`D100-D101` is a word device: it has no bit points"
    );
    let e = m.write_span_words(&d, &[1]).unwrap_err();
    assert_eq!(e.to_string(), "`D100-D101`: 1 values for 2 points");
    let e = m.span(DeviceKind::D, 12280, 10, RBlock::First).unwrap_err();
    assert_eq!(
        e.to_string(),
        "`D12280-D12289`: D12288 is outside the configured range (12288 points)"
    );
    let e = m.span(DeviceKind::X, 0x1FFF, 2, RBlock::First).unwrap_err();
    assert!(e.to_string().starts_with("`X1FFF-X2000`:"), "{e}");
}

/// A place reads and writes exactly what its name does; names that are no
/// place (digits, index modification, strings) have none.
#[test]
fn places_are_their_names_resolved_once() {
    let mut m = mem();
    // Block 1 selected by D100: names still mean block 0's R.
    let selector = m.map.base(DeviceKind::D) + 100;
    m.map.set_r_block(Some(selector));
    m.words[selector as usize] = 1;
    m.set_word(DeviceKind::D, 9, 0x1234).unwrap();
    let names = [
        "X1F", "Y7", "M100", "D0", "D1:u16", "D2:i32", "D4:u32", "D6:f32", "D8.F", "D9.3", "R5",
        "R6:i32", "ZR40", "TN3", "T3", "W1F",
    ];
    for (i, name) in names.iter().enumerate() {
        let spec = DeviceSpec::parse(name).unwrap();
        let place = spec.place(&m).unwrap().unwrap();
        // 32 bits that differ per name, bit 0 ON (a bit takes bit 0).
        let raw = 0x8001_0000u64 | (i as u64 * 0x0F0E + 1);
        m.write_place(&place, raw).unwrap();
        let want = match spec.ty {
            ValueType::Bit => raw & 1,
            ValueType::I32 | ValueType::U32 | ValueType::F32 => raw,
            _ => raw & 0xFFFF,
        };
        assert_eq!(spec.raw(&m).unwrap(), want, "{name}");
        assert_eq!(m.read_place(&place).unwrap(), want, "{name}");
    }
    // D6:f32 (name 7) low word first: D6 = 7·0F0E + 1 = 6963, D7 = 8001.
    assert_eq!(word(&m, DeviceKind::D, 6), 0x6963);
    assert_eq!(word(&m, DeviceKind::D, 7), 0x8001);
    // D8.F is D8's bit 15; D9.3 sets bit 3 of 1234 and leaves the others.
    assert_eq!(word(&m, DeviceKind::D, 8), 0x8000);
    assert_eq!(word(&m, DeviceKind::D, 9), 0x123C);
    // R is block 0's: R5 (name 10) is ZR5 = 10·0F0E + 1 = 968D, not ZR32773.
    assert_eq!(word(&m, DeviceKind::ZR, 5), 0x968D);
    assert_eq!(word(&m, DeviceKind::ZR, 32773), 0);
    for name in ["D0Z0", "X0Z1", "K4M0Z0", "D30:str"] {
        assert!(
            DeviceSpec::parse(name).unwrap().place(&m).is_none(),
            "{name}"
        );
    }
    // K4M0 covers M0-M15 (bits past them ignored); K8M16 is 32 bits from M16.
    let k4 = DeviceSpec::parse("K4M0")
        .unwrap()
        .place(&m)
        .unwrap()
        .unwrap();
    assert!(k4.is_digits() && k4.span().len() == 16);
    m.write_place(&k4, 0xF0_A5C3).unwrap();
    assert_eq!(m.read_place(&k4).unwrap(), 0xA5C3);
    assert_eq!(DeviceSpec::parse("K4M0").unwrap().raw(&m).unwrap(), 0xA5C3);
    assert_eq!(m.get_bit(DeviceKind::M, 0), Ok(true));
    assert_eq!(m.get_bit(DeviceKind::M, 2), Ok(false));
    assert_eq!(m.get_bit(DeviceKind::M, 16), Ok(false));
    let k8 = DeviceSpec::parse("K8M16")
        .unwrap()
        .place(&m)
        .unwrap()
        .unwrap();
    m.write_place(&k8, 0x8000_0001).unwrap();
    let k8_raw = DeviceSpec::parse("K8M16").unwrap().raw(&m).unwrap();
    assert_eq!(k8_raw, 0x8000_0001);
    assert_eq!(m.get_bit(DeviceKind::M, 47), Ok(true));
    let e = DeviceSpec::parse("D12288").unwrap().place(&m).unwrap();
    assert!(e.unwrap_err().to_string().contains("D12288"));
}

/// A place past the end of another configuration's memory is an error,
/// never a panic.
#[test]
fn a_place_of_another_configuration_is_an_error() {
    let mut cfg = DeviceConfig::default();
    let zr = DeviceConfig::default().points(DeviceKind::ZR);
    cfg.set_points(DeviceKind::ZR, zr + 1_000_000);
    let big = DeviceMemory::new(&cfg);
    let mut small = mem();
    let last = zr + 999_998;
    for name in [format!("ZR{last}"), format!("ZR{last}:i32")] {
        let place = DeviceSpec::parse(&name)
            .unwrap()
            .place(&big)
            .unwrap()
            .unwrap();
        let e = small.read_place(&place).unwrap_err().to_string();
        assert!(e.contains(&format!("ZR{last}")), "{e}");
        assert!(small.write_place(&place, 1).is_err(), "{name}");
    }
}
