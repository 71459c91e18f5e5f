// SPDX-License-Identifier: MIT OR Apache-2.0

use super::*;
use proptest::prelude::*;

fn process(name: &str) -> ProcessItem {
    match Item::parse(name).unwrap().kind {
        ItemKind::Process(p) => p,
        other => panic!("{name}: {other:?}"),
    }
}

#[test]
fn the_migration_guides_three_examples() {
    let eb = Item::parse("PNIO:[CTRL3]EB10").unwrap();
    assert_eq!(eb.controller, 3);
    assert_eq!(
        eb.kind,
        ItemKind::Process(ProcessItem {
            area: Area::Input,
            letters: Letters::German,
            format: Format::Byte,
            address: 10,
            bit: 0,
            count: None,
        })
    );
    let record = Item::parse("PNIO:[CTRL1]EDS10,DATA61450,10").unwrap();
    assert_eq!(
        record,
        Item {
            controller: 1,
            kind: ItemKind::Record(RecordItem {
                area: Area::Input,
                letters: Letters::German,
                address: 10,
                index: 0xF00A,
                length: Some(10),
            })
        }
    );
    assert_eq!(
        Item::parse("PNIO:[CTRL3]mode").unwrap().kind,
        ItemKind::Mode
    );
}

#[test]
fn formats_letters_bits_and_arrays() {
    assert_eq!(process("PNIO:[CTRL1]QW4").format, Format::Word);
    assert_eq!(process("PNIO:[CTRL1]QW4").area, Area::Output);
    assert_eq!(process("pnio:[ctrl1]aw4").letters, Letters::German);
    assert_eq!(process("PNIO:[CTRL1]ED0").format, Format::DWord);
    assert_eq!(process("PNIO:[CTRL1]EDWORD0").format, Format::DWord);
    assert_eq!(process("PNIO:[CTRL1]EDINT0").format, Format::DInt);
    assert_eq!(process("PNIO:[CTRL1]IINT2").format, Format::Int);
    assert_eq!(process("PNIO:[CTRL1]IREAL8").format, Format::Real);
    assert_eq!(process("PNIO:[CTRL1]IBYTE8").format, Format::Byte);
    let bit = process("PNIO:[CTRL2]E2.5");
    assert_eq!((bit.format, bit.address, bit.bit), (Format::Bit, 2, 5));
    assert_eq!(process("PNIO:[CTRL2]EX2.5"), bit);
    let bits = process("PNIO:[CTRL2]E2.5,6");
    assert_eq!(bits.span(), (2, 2), "bits 2.5 to 3.2");
    let words = process("PNIO:[CTRL1]EW10,3");
    assert_eq!(words.span(), (10, 6));
}

#[test]
fn names_that_are_no_items_say_why() {
    for (name, says) in [
        ("S7:[CTRL1]EB10", "PNIO:[CTRL"),
        ("PNIO:[CTRL0]EB1", "start at 1"),
        ("PNIO:[CTRL256]EB1", "more than 255"),
        ("PNIO:[CTRL1]MB1", "area"),
        ("PNIO:[CTRL1]EB", "the address expected"),
        ("PNIO:[CTRL1]E3", "a format"),
        ("PNIO:[CTRL1]EX3", "<address>.<bit>"),
        ("PNIO:[CTRL1]E3.8", "more than 7"),
        ("PNIO:[CTRL1]EB3,0", "at least one"),
        ("PNIO:[CTRL1]EB3,5000", "more than the 4096"),
        ("PNIO:[CTRL1]EDS3,DATA70000", "more than 65535"),
        ("PNIO:[CTRL1]EDS3", ",DATA"),
        ("PNIO:[CTRL1]EB3 ", "follows the item"),
        ("PNIO:[CTRL1]modes", "follows the item"),
    ] {
        let e = Item::parse(name).unwrap_err();
        assert!(e.why.contains(says), "{name}: {e}");
        assert!(e.to_string().contains("PNIO:[CTRL1]EB10"), "{e}");
    }
}

#[test]
fn values_are_big_endian_and_bits_count_from_the_lowest() {
    let w = process("PNIO:[CTRL1]EW0,2");
    assert_eq!(
        w.decode(&[0x12, 0x34, 0xFF, 0xFE]).unwrap(),
        Values::Words(vec![0x1234, 0xFFFE])
    );
    let i = process("PNIO:[CTRL1]EINT0,2");
    assert_eq!(
        i.decode(&[0x12, 0x34, 0xFF, 0xFE]).unwrap(),
        Values::Ints(vec![0x1234, -2])
    );
    let r = process("PNIO:[CTRL1]EREAL0");
    assert_eq!(
        r.decode(&1.5f32.to_be_bytes()).unwrap(),
        Values::Reals(vec![1.5])
    );
    let b = process("PNIO:[CTRL1]E0.7,2");
    assert_eq!(
        b.decode(&[0x80, 0x00]).unwrap(),
        Values::Bits(vec![true, false])
    );
    // Writing bits leaves the others of their bytes.
    let mut bytes = [0xFF, 0xFF];
    b.encode(&Values::Bits(vec![false, false]), &mut bytes)
        .unwrap();
    assert_eq!(bytes, [0x7F, 0xFE]);
    assert_eq!(
        w.decode(&[1, 2, 3]),
        Err(ValueError::Span { want: 4, got: 3 })
    );
    assert_eq!(
        w.encode(&Values::Bytes(vec![1, 2, 3, 4]), &mut [0; 4]),
        Err(ValueError::Format {
            want: Format::Word,
            got: Format::Byte
        })
    );
    assert_eq!(
        w.encode(&Values::Words(vec![1]), &mut [0; 4]),
        Err(ValueError::Count { want: 2, got: 1 })
    );
}

fn any_item() -> impl Strategy<Value = Item> {
    let area = prop_oneof![Just(Area::Input), Just(Area::Output)];
    let letters = prop_oneof![Just(Letters::German), Just(Letters::English)];
    let format = prop_oneof![
        Just(Format::Bit),
        Just(Format::Byte),
        Just(Format::Word),
        Just(Format::Int),
        Just(Format::DWord),
        Just(Format::DInt),
        Just(Format::Real),
    ];
    let process = (
        area.clone(),
        letters.clone(),
        format,
        0u32..100_000,
        0u8..8,
        prop::option::of(1u16..256),
    )
        .prop_map(|(area, letters, format, address, bit, count)| {
            ItemKind::Process(ProcessItem {
                area,
                letters,
                format,
                address,
                bit: if format == Format::Bit { bit } else { 0 },
                count,
            })
        });
    let record = (
        area,
        letters,
        0u32..100_000,
        any::<u16>(),
        prop::option::of(1u16..=4096),
    )
        .prop_map(|(area, letters, address, index, length)| {
            ItemKind::Record(RecordItem {
                area,
                letters,
                address,
                index,
                length,
            })
        });
    (
        1u8..=255,
        prop_oneof![Just(ItemKind::Mode), process, record],
    )
        .prop_map(|(controller, kind)| Item { controller, kind })
}

proptest! {
    /// Every item reads back from its canonical name as itself.
    #[test]
    fn a_name_reads_back_as_its_item(item in any_item()) {
        let name = item.to_string();
        prop_assert_eq!(Item::parse(&name), Ok(item), "{}", name);
        prop_assert_eq!(Item::parse(&name.to_lowercase()), Ok(item));
    }

    /// No text panics the parser.
    #[test]
    fn no_text_panics_the_parser(text in "(PNIO:\\[CTRL[0-9]{0,4}\\])?[EAIQXBWDSNTRL.,0-9a-z]{0,20}") {
        let _ = Item::parse(&text);
    }

    /// Bytes decoded and encoded again are the bytes (for bit items, the bits it names).
    #[test]
    fn bytes_decode_and_encode_to_themselves(item in any_item(), seed in any::<u64>()) {
        let ItemKind::Process(p) = item.kind else { return Ok(()) };
        let (_, len) = p.span();
        let bytes: Vec<u8> = (0..len).map(|k| (seed >> (k % 8 * 8)) as u8 ^ k as u8).collect();
        let values = p.decode(&bytes).unwrap();
        prop_assert_eq!(values.len(), p.values());
        let mut again = vec![0u8; len];
        if p.format == Format::Bit {
            again.clone_from(&bytes);
        }
        // Exact for REAL too, NaN payloads included: from_be_bytes and to_be_bytes keep bits.
        p.encode(&values, &mut again).unwrap();
        prop_assert_eq!(again, bytes);
    }
}
