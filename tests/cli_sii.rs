//! `edsgen sii`: the EC-TX508's SII image written to a file, read back by `edsgen dump` as the
//! ESI's identity, SyncManagers and PDOs; a file that is not an ESI device exits 2.

use std::path::PathBuf;
use std::process::{Command, Output};

const EDSGEN: &str = env!("CARGO_BIN_EXE_edsgen");

fn run(args: &[&str]) -> Output {
    Command::new(EDSGEN)
        .args(args)
        .env("NO_COLOR", "1")
        .output()
        .unwrap()
}

fn out_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("edsgen-sii-{}-{test}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn the_ec_tx508_image_is_written_and_dumps_back() {
    let bin = out_dir("ec_tx508").join("eeprom.bin");
    let out = run(&["sii", "eds/ec-tx508.xml", "-o", bin.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        format!("wrote 1076 bytes (538 words) of SII to {}\n", bin.display())
    );
    let image = std::fs::read(&bin).unwrap();
    // Identity words 0x08-0x0D.
    assert_eq!(image[16..28], [0xD8, 4, 0, 0, 0x52, 0x92, 0, 0, 1, 0, 0, 0]);
    let out = run(&["dump", bin.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["device_info"]["vendor_number"], 0x04D8);
    assert_eq!(json["device_info"]["product_number"], 0x9252);
    let ec = &json["ethercat"];
    assert_eq!(ec["type_name"], "EC-TX508");
    assert_eq!(ec["rx_pdos"][0]["entries"][2]["name"], "Target speed");
    assert_eq!(ec["tx_pdos"].as_array().unwrap().len(), 4);
    assert_eq!(ec["sync_managers"][3]["start_address"], 0x1C00);
}

#[test]
fn a_canopen_file_has_no_sii_and_a_short_image_reads_nothing() {
    let dir = out_dir("refused");
    let out = run(&[
        "sii",
        "eds/cp301.eds",
        "-o",
        dir.join("x.bin").to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "error: eds/cp301.eds: not an EtherCAT device: an SII image is built from an ESI file\n"
    );
    let short = dir.join("short.bin");
    std::fs::write(&short, [0u8; 6]).unwrap();
    let out = run(&["dump", short.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("EDS818"),
        "{out:?}"
    );
}
