//! The Goodrive350 PROFIBUS-DP card's GSD (`eds/goodrive350-dp.gsd`) against the manual's
//! chapter 2: Table 2-4's baud rates, Figure 2-4's 4 PKW + 12 PZD module, and a clean validate.

use std::path::Path;

use edsgen_model::model::{DpBaudRate, Format, TextEncoding};
use edsgen_model::read::read_file;
use edsgen_model::validate::validate;

fn card() -> edsgen_model::read::Read {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../eds/goodrive350-dp.gsd");
    read_file(&path).expect("the card's GSD")
}

#[test]
fn reads_clean() {
    let read = card();
    assert_eq!(read.device.source.format, Format::Gsd);
    assert_eq!(read.device.source.encoding, TextEncoding::Ascii);
    assert_eq!(read.diagnostics, []);
    assert_eq!(validate(&read.device), []);
}

/// Table 2-4: settings 0-8 and 10 (9 Mbit/s is no PROFIBUS rate: not declared).
#[test]
fn baud_rates_are_table_2_4() {
    let read = card();
    let dp = read.device.dp().unwrap();
    let rates: Vec<(u32, Option<u32>)> = dp
        .baud_rates
        .iter()
        .map(|b| (b.rate.bits_per_second(), b.max_tsdr))
        .collect();
    assert_eq!(
        rates,
        [
            (9_600, Some(60)),
            (19_200, Some(60)),
            (45_450, Some(60)),
            (93_750, Some(60)),
            (187_500, Some(60)),
            (500_000, Some(100)),
            (1_500_000, Some(150)),
            (3_000_000, Some(250)),
            (6_000_000, Some(450)),
            (12_000_000, Some(800)),
        ]
    );
    assert!(!dp.baud_rates.iter().any(|b| b.rate == DpBaudRate::B31k25));
    assert!(!dp.auto_baud && !dp.set_slave_add);
}

/// Figure 2-4: PKW1-PKW4 then CW/SW and PZD2-PZD12, 16 words each way in one module.
#[test]
fn one_module_of_4_pkw_and_12_pzd() {
    let read = card();
    let dp = read.device.dp().unwrap();
    assert_eq!(dp.ident_number.as_ref().map(|i| i.value), Some(0x0350));
    assert_eq!(dp.modules.len(), 1);
    let module = &dp.modules[0];
    assert_eq!(module.name, "4 PKW + 12 PZD");
    assert_eq!(module.config, [0xF3, 0xFB]);
    let ids = module.identifiers();
    assert_eq!(
        ids.iter()
            .map(|i| (i.input_bytes, i.output_bytes, i.words, i.consistent))
            .collect::<Vec<_>>(),
        [(8, 8, true, true), (24, 24, true, true)]
    );
    assert_eq!(module.io_lengths(), (32, 32));
    assert!(!dp.modular_station);
    assert_eq!(
        (
            dp.max_input_len.as_ref().map(|l| l.value),
            dp.max_output_len.as_ref().map(|l| l.value),
            dp.max_data_len.as_ref().map(|l| l.value)
        ),
        (Some(32), Some(32), Some(64))
    );
    assert_eq!(dp.max_diag_data_len, Some(6));
    assert!(dp.freeze && dp.sync && !dp.fail_safe);
    assert_eq!(dp.default_user_prm_data(), Vec::<u8>::new());
}
