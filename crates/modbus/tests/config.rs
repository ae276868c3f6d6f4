//! The plc.toml `[modbus]` table.

mod common;

use common::*;
use softplc_core::device::DeviceKind::*;
use softplc_modbus::{Map, Preset, Range, Request, Slave, Table, MAP_KEYS, SLAVE_KEYS};

fn modbus(src: &str) -> toml::Table {
    let doc: toml::Table = toml::from_str(src).unwrap();
    doc["modbus"].as_table().unwrap().clone()
}

fn map(src: &str) -> Result<Map, String> {
    Map::from_toml(&modbus(src))
}

#[test]
fn presets() {
    assert_eq!(map("[modbus]\n").unwrap(), Map::q_default());
    assert_eq!(map("[modbus]\ndialect = \"aplc\"\n").unwrap(), Map::aplc());
    assert_eq!(
        Map::from_toml_with(&modbus("[modbus]\n"), Preset::find("aplc").unwrap()).unwrap(),
        Map::aplc()
    );
    assert_eq!(
        map("[modbus]\ndialect = \"fx\"\n").unwrap_err(),
        "[modbus] dialect: unknown dialect \"fx\" (expected \"q\" or \"aplc\")"
    );
    assert_eq!(Map::q_default().validate(), Ok(()));
    assert_eq!(Map::aplc().validate(), Ok(()));
    assert!(Map::q_default()
        .check_devices(&Default::default())
        .is_empty());
    assert!(Map::aplc().check_devices(&Default::default()).is_empty());
}

/// Presets are named data: the `dialect` key's names, and every CPU
/// profile's `doors.modbus`, find one.
#[test]
fn presets_are_found_by_name() {
    for (name, want) in [
        ("q", Map::q_default()),
        ("melsec", Map::q_default()),
        ("MELSEC-Q", Map::q_default()),
        (" Aplc ", Map::aplc()),
    ] {
        assert_eq!(Preset::find(name).unwrap().map(), want, "{name}");
        let src = format!("[modbus]\ndialect = \"{}\"\n", name.trim());
        assert_eq!(map(&src).unwrap(), want, "{name}");
    }
    assert_eq!(Preset::find("fx"), None);
    for p in softplc_core::profile::all() {
        let preset = Preset::find(p.doors.modbus).unwrap();
        assert_eq!(preset.name(), p.doors.modbus, "{}", p.model);
    }
    let aplc = softplc_core::profile::aplc();
    assert_eq!(Preset::find(aplc.doors.modbus).unwrap().map(), Map::aplc());
    let q = softplc_core::profile::default_profile();
    assert_eq!(
        Preset::find(q.doors.modbus).unwrap().map(),
        Map::q_default()
    );
}

#[test]
fn custom_tables_replace_the_preset() {
    let m = map(r#"
[modbus]
coils = [
    { address = 0, device = "Y0", count = 16 },
    { address = 100, device = "M100", count = 10 },
    { address = 200, device = "T0", count = 8 },
]
[[modbus.holding_registers]]
address = 0
device = "D1000"
count = 100
[[modbus.holding_registers]]
address = 1000
device = "C0"
count = 4
pairs = true
[[modbus.holding_registers]]
address = 2000
device = "SD0"
count = 10
writable = [[5, 6]]
[[modbus.holding_registers]]
address = 3000
device = "W10"
count = 16
ignore_writes = true
"#)
    .unwrap();
    let coils: Vec<_> = m
        .ranges
        .iter()
        .filter(|r| r.table == Table::Coils)
        .collect();
    assert_eq!(coils.len(), 3);
    // T in a bit table is the contact; C in a register table the current value.
    assert_eq!(*coils[2], Range::new(Table::Coils, 200, 8, TS, 0));
    assert_eq!(m.device_at(Table::HoldingRegisters, 1003), Some((CN, 1)));
    assert_eq!(m.device_at(Table::HoldingRegisters, 99), Some((D, 1099)));
    assert_eq!(m.device_at(Table::HoldingRegisters, 100), None);
    assert_eq!(m.device_at(Table::HoldingRegisters, 3015), Some((W, 0x1F)));
    // Untouched tables keep the preset.
    assert_eq!(m.device_at(Table::DiscreteInputs, 8191), Some((X, 0x1FFF)));

    let mut cpu = cpu();
    let mut slave = Slave::new(1);
    let mut send = |req: Request, cpu: &mut softplc_core::engine::Cpu| {
        let f = softplc_modbus::Frame::new(softplc_modbus::Proto::Tcp, 1, 1, req.to_pdu());
        softplc_modbus::serve(&mut slave, &m, &f, cpu).unwrap()[7..].to_vec()
    };
    assert_eq!(
        send(
            Request::ReadCoils {
                address: 16,
                quantity: 1
            },
            &mut cpu
        ),
        [0x81, 2]
    );
    send(
        Request::WriteSingleRegister {
            address: 5,
            value: 3,
        },
        &mut cpu,
    );
    assert_eq!(word(&cpu, D, 1005), 3);
    send(
        Request::WriteMultipleRegisters {
            address: 2004,
            values: vec![1, 2, 3, 4],
        },
        &mut cpu,
    );
    assert_eq!([4, 5, 6, 7].map(|n| word(&cpu, SD, n)), [0, 2, 3, 0]);
    send(
        Request::WriteSingleRegister {
            address: 3000,
            value: 3,
        },
        &mut cpu,
    );
    assert_eq!(word(&cpu, W, 0x10), 0);
    // Pairs: the even register is the high word.
    set_word(&mut cpu, CN, 1, 0x1234);
    assert_eq!(
        send(
            Request::ReadHoldingRegisters {
                address: 1002,
                quantity: 2
            },
            &mut cpu
        ),
        [3, 4, 0, 0, 0x12, 0x34]
    );
    // The Q dialect spans ranges, but only over mapped addresses.
    assert_eq!(
        send(
            Request::ReadHoldingRegisters {
                address: 99,
                quantity: 2
            },
            &mut cpu
        ),
        [0x83, 2]
    );
}

#[test]
fn functions_can_be_restricted() {
    let m = map("[modbus]\nfunctions = [1, 3]\n").unwrap();
    assert_eq!(m.functions, [1, 3]);
    assert!(map("[modbus]\nfunctions = [1, 7]\n")
        .unwrap_err()
        .contains("function code 7"));
    assert!(map("[modbus]\ndialect = \"aplc\"\nfunctions = [4]\n").is_err());
}

#[test]
fn bad_entries() {
    let e = |entry: &str| map(&format!("[modbus]\ncoils = [{entry}]\n")).unwrap_err();
    assert_eq!(
        e(r#"{ address = 0, device = "D0", count = 1 }"#),
        "[modbus] coils[0]: device \"D0\" is a word device; coils need bit devices"
    );
    assert_eq!(
        e(r#"{ address = 0, device = "K4M0", count = 1 }"#),
        "[modbus] coils[0]: device \"K4M0\" is not a device name"
    );
    assert_eq!(
        e(r#"{ address = 65535, device = "M0", count = 2 }"#),
        "[modbus] coils[0]: count 2 does not fit the 0-65535 address space from 65535"
    );
    assert_eq!(
        e(r#"{ address = 70000, device = "M0", count = 1 }"#),
        "[modbus] coils[0]: address 70000 is over 65535"
    );
    assert!(e(r#"{ address = 0, device = "M0", count = 0 }"#).contains("count 0"));
    assert!(e(r#"{ address = 0, device = "M0" }"#).contains("count"));
    assert!(e(r#"{ address = 0, device = "M0", count = 1, colour = 1 }"#).contains("colour"));
    assert!(e(r#"{ address = 0, device = "M0", count = 2, pairs = true }"#).contains("pairs"));
    assert_eq!(
        e(
            r#"{ address = 0, device = "M0", count = 10 }, { address = 9, device = "L0", count = 1 }"#
        ),
        "coils: ranges 0-9 → M0-M9 and 9-9 → L0-L0 overlap"
    );
    assert!(
        e(r#"{ address = 0, device = "M0", count = 1, writable = [[3, 1]] }"#).contains("reversed")
    );
    assert!(map("[modbus]\nholding_registers = [{ address = 0, device = \"D0\", count = 3, pairs = true }]\n")
        .unwrap_err()
        .contains("even count"));
}

#[test]
fn slave_keys() {
    let s = Slave::from_toml(&modbus(
        "[modbus]\nunit_id = 8\nread_only = true\ntcp_any_unit = false\n",
    ))
    .unwrap();
    assert_eq!((s.unit_id, s.read_only, s.tcp_any_unit), (8, true, false));
    assert_eq!(
        Slave::from_toml(&modbus("[modbus]\n")).unwrap(),
        Slave::new(1)
    );
    assert!(Slave::from_toml(&modbus("[modbus]\nunit_id = 0\n")).is_err());
    assert!(Slave::from_toml(&modbus("[modbus]\nunit_id = 248\n")).is_err());
    assert!(Slave::from_toml(&modbus("[modbus]\nread_only = 1\n")).is_err());
    // The two key lists do not overlap, and the map ignores the slave's keys.
    assert!(MAP_KEYS.iter().all(|k| !SLAVE_KEYS.contains(k)));
    assert_eq!(map("[modbus]\nunit_id = 3\n").unwrap(), Map::q_default());
}
