//! The reader and the GSD rules on small files: every part of the model, and each rule with its
//! span.

use std::path::Path;

use edsgen_model::model::{DpBaudRate, PrmType, PrmValues, Span, TextEncoding};
use edsgen_model::read::read_bytes;
use edsgen_model::validate::validate;

const GOOD: &str = "\
; a test slave
#profibus_dp
GSD_Revision = 3
Vendor_Name = \"Acme\"
MODEL_NAME = \"Pump; DP\"   ; a comment after a value
Revision = \"1\"
OrderNumber = \"A-1\"
Ident_Number = 0x1234
Protocol_Ident = 0
Station_Type = 0
9.6_supp = 1
MaxTsdr_9.6 = 60
1.5M_supp = 1
MaxTsdr_1.5M = 150
Freeze_Mode_supp = 1
Sync_Mode_supp = 0
Fail_Safe = 1
Set_Slave_Add_supp = 0
Min_Slave_Intervall = 6
Max_Diag_Data_Len = 16
Modular_Station = 1
Max_Module = 2
Max_Input_Len = 32
Max_Output_Len = 32
Max_Data_Len = 64
User_Prm_Data_Len = 3
Max_User_Prm_Data_Len = 3
Ext_User_Prm_Data_Const(0) = 0x00, \\
                             0x00,0x00
Ext_User_Prm_Data_Ref(0) = 1
Ext_User_Prm_Data_Ref(1) = 2
PrmText = 1
Text(0) = \"off\"
Text(1) = \"on\"
EndPrmText
ExtUserPrmData = 1 \"Mode\"
Bit(3) 1 0-1
Prm_Text_Ref = 1
EndExtUserPrmData
ExtUserPrmData = 2 \"Speed\"
Unsigned16 500 0-1000
EndExtUserPrmData
Module = \"PKW + 12 PZD\" 0xF3, 0xFB
1
EndModule
Module = \"special\" 0xC2,0x41,0x83,0xAA,0xBB
2
EndModule
SlotDefinition
Slot(1) = \"Slot 1\" 1 1-2
EndSlotDefinition
Unit_Diag_Bit(16) = \"Overheat\"
Unit_Diag_Area = 24-25
Value(1) = \"Fault A\"
Unit_Diag_Area_End
Acme_Extension_Thing = 7
";

#[test]
fn reads_every_part() {
    let read = read_bytes(Path::new("a.gsd"), GOOD.as_bytes());
    let dp = read.device.dp().unwrap();
    assert_eq!(dp.gsd_revision, Some(3));
    assert_eq!(dp.vendor_name.as_deref(), Some("Acme"));
    assert_eq!(dp.model_name.as_deref(), Some("Pump; DP"));
    assert_eq!(dp.ident_number.as_ref().map(|i| i.value), Some(0x1234));
    assert_eq!(
        dp.ident_number.as_ref().map(|i| i.span),
        Some(Span::new(8, 1, 21))
    );
    let rates: Vec<_> = dp.baud_rates.iter().map(|b| (b.rate, b.max_tsdr)).collect();
    assert_eq!(
        rates,
        [(DpBaudRate::B9k6, Some(60)), (DpBaudRate::B1M5, Some(150))]
    );
    assert!(dp.freeze && !dp.sync && dp.fail_safe && !dp.set_slave_add);
    assert_eq!(
        (dp.min_slave_interval, dp.max_diag_data_len),
        (Some(6), Some(16))
    );
    assert!(dp.modular_station);
    assert_eq!(dp.max_module, Some(2));
    assert_eq!(dp.prm_consts[0].bytes, [0, 0, 0]);
    assert_eq!(
        dp.prm_texts[0].texts,
        [(0, "off".to_owned()), (1, "on".to_owned())]
    );
    assert_eq!(dp.prm_definitions[0].data_type, PrmType::Bit(3));
    assert_eq!(dp.prm_definitions[0].text_ref, Some(1));
    assert_eq!(dp.prm_definitions[1].values, PrmValues::Range(0, 1000));
    // Bit 3 of byte 0 set, 500 big-endian at bytes 1-2.
    assert_eq!(dp.default_user_prm_data(), [0x08, 0x01, 0xF4]);
    assert_eq!(dp.modules[0].config, [0xF3, 0xFB]);
    assert_eq!(dp.modules[0].reference, Some(1));
    assert_eq!(dp.modules[0].io_lengths(), (32, 32));
    assert_eq!(dp.modules[1].io_lengths(), (4, 4));
    assert_eq!(dp.slots[0].allowed, [1, 2]);
    assert_eq!(dp.unit_diag.len(), 2);
    assert_eq!(dp.unit_diag[1].bits, (24, 25));
    assert_eq!(dp.other[0].key, "Acme_Extension_Thing");
    assert_eq!(read.device.source.encoding, TextEncoding::Ascii);
    let codes: Vec<_> = read
        .diagnostics
        .iter()
        .map(|d| (d.rule.code, d.span))
        .collect();
    assert_eq!(codes, [("GSD005", Some(Span::new(56, 1, 24)))]);
    assert_eq!(validate(&read.device), []);
}

fn codes(text: &str) -> Vec<(&'static str, u32)> {
    let read = read_bytes(Path::new("a.gsd"), text.as_bytes());
    let mut all = read.diagnostics.clone();
    all.extend(validate(&read.device));
    edsgen_model::diag::sort(&mut all);
    all.iter()
        .map(|d| (d.rule.code, d.span.map_or(0, |s| s.line)))
        .collect()
}

const HEAD: &str = "#Profibus_DP\nIdent_Number = 1\n9.6_supp = 1\nMaxTsdr_9.6 = 60\n";

#[test]
fn each_rule_with_its_line() {
    let cases: [(&str, Vec<(&str, u32)>); 11] = [
        ("Ident_Number = 1\nModule = \"m\" 0x10\nEndModule\n", vec![("GSD001", 1)]),
        ("what is this\nModule = \"m\" 0x10\nEndModule\n", vec![("GSD002", 5)]),
        ("Model_Name = \"a\"\nModel_Name = \"b\"\nModule = \"m\" 0x10\nEndModule\n", vec![("GSD004", 6)]),
        ("Max_Input_Len = x\nModule = \"m\" 0x10\nEndModule\n", vec![("GSD006", 5)]),
        ("Module = \"m\" 0x10\n", vec![("GSD007", 5)]),
        ("Module = \"m\" 0x40\nEndModule\n", vec![("GSD010", 5)]),
        ("Max_Input_Len = 4\nModule = \"m\" 0x17\nEndModule\n", vec![("GSD011", 6)]),
        (
            "User_Prm_Data_Len = 1\nExt_User_Prm_Data_Ref(0) = 9\nModule = \"m\" 0x10\nEndModule\n",
            vec![("GSD012", 6)],
        ),
        (
            "User_Prm_Data_Len = 1\nExt_User_Prm_Data_Ref(0) = 1\nExtUserPrmData = 1 \"x\"\nUnsigned16 0 0-10\nEndExtUserPrmData\nModule = \"m\" 0x10\nEndModule\n",
            vec![("GSD013", 6)],
        ),
        (
            "ExtUserPrmData = 1 \"x\"\nUnsigned8 20 0-10\nEndExtUserPrmData\nModule = \"m\" 0x10\nEndModule\n",
            vec![("GSD014", 6)],
        ),
        ("12M_supp = 1\n", vec![("GSD017", 0), ("GSD016", 5)]),
    ];
    for (n, (body, expected)) in cases.into_iter().enumerate() {
        let text = if n == 0 {
            body.to_owned()
        } else {
            format!("{HEAD}{body}")
        };
        let mut got = codes(&text);
        got.retain(|(code, _)| n == 0 || *code != "GSD016" || n == 10);
        assert_eq!(got, expected, "case {n}:\n{text}");
    }
}

#[test]
fn latin1_and_utf8() {
    let latin1 = b"#Profibus_DP\nVendor_Name = \"M\xFCller\"\n";
    let read = read_bytes(Path::new("a.gsd"), latin1);
    assert_eq!(read.device.source.encoding, TextEncoding::Latin1);
    assert_eq!(
        read.device.dp().unwrap().vendor_name.as_deref(),
        Some("M\u{fc}ller")
    );
    let utf8 = "#Profibus_DP\nVendor_Name = \"Müller\"\n";
    let read = read_bytes(Path::new("a.gsd"), utf8.as_bytes());
    assert_eq!(read.device.source.encoding, TextEncoding::Utf8);
    let utf8_codes: Vec<_> = read
        .diagnostics
        .iter()
        .map(|d| (d.rule.code, d.span))
        .collect();
    assert_eq!(utf8_codes, [("GSD003", Some(Span::new(2, 17, 1)))]);
}

#[test]
fn detected_by_content() {
    use edsgen_model::model::Format;
    use edsgen_model::read::detect_format;
    assert_eq!(
        detect_format(Path::new("x.txt"), b"; c\n\n#PROFIBUS_DP\n"),
        Format::Gsd
    );
    assert_eq!(detect_format(Path::new("x.GSE"), b""), Format::Gsd);
    assert_eq!(
        detect_format(Path::new("x.txt"), b"[FileInfo]\n"),
        Format::Eds
    );
}

/// A misspelt keyword gets the keyword it is a letter or two from; another keyword does not.
#[test]
fn an_unknown_keyword_near_a_known_one_says_did_you_mean() {
    let text = "#Profibus_DP\nGSD_Revision = 1\nMin_Slave_Interval = 1\nFamily_Name = \"x\"\n";
    let read = read_bytes(Path::new("t.gsd"), text.as_bytes());
    let found: Vec<_> = read
        .diagnostics
        .iter()
        .filter(|d| d.rule.code == "GSD005")
        .map(|d| {
            (
                d.span.map(|s| s.line),
                d.message.as_str(),
                d.help.as_deref(),
            )
        })
        .collect();
    assert_eq!(
        found,
        [
            (
                Some(3),
                "unknown keyword `Min_Slave_Interval` (kept, not interpreted)",
                Some("did you mean `Min_Slave_Intervall`?")
            ),
            (
                Some(4),
                "unknown keyword `Family_Name` (kept, not interpreted)",
                None
            ),
        ]
    );
}

/// GSD016 fires on a supported rate without MaxTsdr, with a help line; a MaxTsdr for a rate not
/// supported (vendors fill the whole table) is harmless and not reported.
#[test]
fn gsd016_only_a_supported_rate_without_maxtsdr() {
    let text = "#Profibus_DP\n9.6_supp = 1\nMaxTsdr_9.6 = 60\nMaxTsdr_19.2 = 60\nMaxTsdr_1.5M = 150\n12M_supp = 1\n";
    let read = read_bytes(Path::new("t.gsd"), text.as_bytes());
    let found: Vec<_> = validate(&read.device)
        .into_iter()
        .filter(|d| d.rule.code == "GSD016")
        .map(|d| (d.span.map(|s| s.line), d.message, d.help))
        .collect();
    assert_eq!(
        found,
        [(
            Some(6),
            "12M_supp without MaxTsdr_12M: a master cannot know how long to wait".to_owned(),
            Some("add `MaxTsdr_12M = N`, the slave's longest response time at that rate in bit times (the table of the slave's manual or ASIC), or remove `12M_supp`".to_owned())
        )]
    );
}
