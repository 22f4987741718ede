//! How a machine file's tables become `edsgen simulate` runs: the arguments and the fault
//! targets of a segment of EC-TX508s and of several PROFINET devices on one interface.

use std::path::Path;

use super::{file, launches};

fn strings(words: &[&str]) -> Vec<String> {
    words.iter().map(|w| (*w).to_owned()).collect()
}

#[test]
fn two_ec_tx508s_are_one_segment_with_faults_by_position() {
    let text = "[[ethercat]]\ninterface = \"veth1\"\ndevices = [\"ec-tx508\", \"ec-tx508\"]\n";
    let machine = file::parse(text, Path::new(".")).expect("a machine");
    let names: Vec<&str> = machine.sections[0]
        .devices
        .iter()
        .map(|d| d.name.as_str())
        .collect();
    assert_eq!(names, ["ec-tx508@0", "ec-tx508@1"]);
    let runs = launches(&machine);
    assert_eq!(runs.len(), 1);
    assert_eq!(
        runs[0].args,
        strings(&[
            "simulate",
            "--ethercat",
            "veth1",
            "--card",
            "ec-tx508",
            "--card",
            "ec-tx508",
            "--faults-on-stdin"
        ])
    );
    let targets: Vec<(&str, Option<&str>)> = runs[0]
        .faulted
        .iter()
        .map(|f| (f.name.as_str(), f.target.as_deref()))
        .collect();
    assert_eq!(
        targets,
        [("ec-tx508@0", Some("0")), ("ec-tx508@1", Some("1"))]
    );
}

#[test]
fn one_ec_tx508_takes_bare_faults() {
    let text = "[[ethercat]]\ninterface = \"veth1\"\ndevices = [\"ec-tx508\"]\n";
    let machine = file::parse(text, Path::new(".")).expect("a machine");
    let runs = launches(&machine);
    assert_eq!(runs[0].faulted[0].name, "ec-tx508");
    assert_eq!(runs[0].faulted[0].target, None);
}

#[test]
fn profinet_devices_give_their_ips_in_order_cards_first_and_faults_by_name() {
    let text = "[[profinet]]\ninterface = \"veth2\"\ndevices = [\n\
        { device = \"goodrive350-pn\", name = \"drive-a\", ip = \"10.0.0.11/24\" },\n\
        { device = \"goodrive350-pn\", name = \"drive-b\" },\n]\n";
    let machine = file::parse(text, Path::new(".")).expect("a machine");
    let runs = launches(&machine);
    assert_eq!(
        runs[0].args,
        strings(&[
            "simulate",
            "--profinet",
            "veth2",
            "--card",
            "goodrive350-pn@drive-a",
            "--card",
            "goodrive350-pn@drive-b",
            "--ip",
            "10.0.0.11/24",
            "--ip",
            "-",
            "--faults-on-stdin"
        ])
    );
    let targets: Vec<(&str, Option<&str>)> = runs[0]
        .faulted
        .iter()
        .map(|f| (f.name.as_str(), f.target.as_deref()))
        .collect();
    assert_eq!(
        targets,
        [("drive-a", Some("drive-a")), ("drive-b", Some("drive-b"))]
    );
}

/// The directory of the model's modular GSD fixture (`modular.gsd`).
fn fixtures() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("model/src/model/modules")
}

#[test]
fn a_modular_gsd_slave_gets_its_modules_after_its_file() {
    let text = "[[profibus]]\ntty = \"/dev/ttyS1\"\ndevices = [\n\
        \"goodrive350-dp@3\",\n\
        { device = \"modular.gsd@5\", modules = [\"0 PKW, 2 PZD (PPO 3)\", \"3=16 words out\"] },\n]\n";
    let machine = file::parse(text, &fixtures()).expect("a machine");
    let runs = launches(&machine);
    let gsd = fixtures().join("modular.gsd@5").display().to_string();
    assert_eq!(
        runs[0].args,
        strings(&[
            "simulate",
            "--profibus",
            "/dev/ttyS1",
            "--card",
            "goodrive350-dp@3",
            &gsd,
            "--module",
            "0 PKW, 2 PZD (PPO 3)",
            "--module",
            "3=16 words out",
        ])
    );
}

#[test]
fn a_profinet_device_passes_its_access_point_and_an_ethercat_one_its_modules() {
    let dir = tempdir();
    std::fs::write(dir.join("d.xml"), "").expect("written");
    let planned = super::model::Planned {
        name: "d".to_owned(),
        source: super::model::Source::File(dir.join("d.xml"), None),
        address: super::model::Address::Pn {
            name: Some("dev-a".to_owned()),
            ip: None,
        },
        modules: strings(&["1=MOD_8DI"]),
        access_point: Some("DAP 2".to_owned()),
        at: 0,
    };
    let file = format!("{}@dev-a", dir.join("d.xml").display());
    assert_eq!(
        super::device_args(super::model::Bus::Profinet, &planned),
        strings(&[&file, "--module", "1=MOD_8DI", "--access-point", "DAP 2"])
    );
    let planned = super::model::Planned {
        source: super::model::Source::File(dir.join("d.xml"), Some("x00001234".to_owned())),
        address: super::model::Address::Position(0),
        access_point: None,
        ..planned
    };
    assert_eq!(
        super::device_args(super::model::Bus::EtherCat, &planned),
        strings(&[
            &dir.join("d.xml").display().to_string(),
            "--device",
            "#x00001234",
            "--module",
            "1=MOD_8DI"
        ])
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// A fresh directory under the system's temporary one.
fn tempdir() -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("edsgen-machine-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    dir
}

/// The problems of a machine file, `LINE:COLUMN: MESSAGE` each.
fn problems(text: &str) -> Vec<String> {
    match file::parse(text, &fixtures()) {
        Ok(_) => Vec::new(),
        Err(problems) => problems
            .iter()
            .map(|p| format!("{}:{}: {}", p.line, p.column, p.message))
            .collect(),
    }
}

#[test]
fn modules_the_description_refuses_are_its_eds708_at_the_line() {
    let text = "[[profibus]]\ntty = \"/dev/ttyS1\"\ndevices = [\n\
        { device = \"modular.gsd@5\", modules = [\"8 DI\"] },\n\
        { device = \"modular.gsd@6\", modules = [\"PPO 9\"] },\n]\n";
    assert_eq!(
        problems(text),
        [
            "4:29: EDS708: slot 1 (\"Drive\") does not take module \"8 DI\"",
            "5:29: EDS708: slot 1: no module \"PPO 9\"; did you mean:\n  \"8 DI\"\n  \"16 words out\"\n  \"4 PKW, 2 PZD (PPO 1)\"",
        ]
    );
}

#[test]
fn modules_on_a_card_or_a_canopen_or_enip_device_are_refused() {
    let text = "[[profibus]]\ntty = \"/dev/ttyS1\"\n\
        devices = [{ device = \"goodrive350-dp@3\", modules = [\"PPO 3\"] }]\n\
        [[canopen]]\nbus = \"127.0.0.1:29536\"\n\
        devices = [{ device = \"cp301@2\", modules = [\"x\"] }]\n\
        [[enip]]\n\
        devices = [{ device = \"goodrive350-enip\", address = \"10.0.0.21\", access_point = \"x\" }]\n";
    assert_eq!(
        problems(text),
        [
            "3:43: `goodrive350-dp@3` is a bundled card: its modules are its own (`modules` is for a modular device's file)",
            "6:34: `modules` is for a modular device in [[profibus]], [[profinet]] or [[ethercat]]: a [[canopen]] device takes none",
            "8:66: `access_point` is for a modular device in [[profibus]], [[profinet]] or [[ethercat]]: a [[enip]] device takes none",
        ]
    );
}

#[test]
fn the_example_machine_is_read_with_its_modules() {
    let example = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/machine.toml");
    let machine = file::read(&example).expect("the example reads");
    let runs = launches(&machine);
    let dp = runs
        .iter()
        .find(|r| r.args[1] == "--profibus")
        .expect("a DP line");
    let gsd = example
        .parent()
        .expect("examples/")
        .join("../eds/goodrive350-dp.gsd@4");
    assert_eq!(
        dp.args,
        strings(&[
            "simulate",
            "--profibus",
            "/tmp/edsgen-dp-line",
            "--card",
            "goodrive350-dp@3",
            &gsd.display().to_string(),
            "--module",
            "1=4 PKW + 12 PZD",
        ])
    );
}

#[test]
fn profinet_and_ethercat_modules_are_checked_against_their_files() {
    let eds = Path::new(env!("CARGO_MANIFEST_DIR")).join("eds");
    let text = "[[profinet]]\ninterface = \"veth2\"\ndevices = [\n\
        { device = \"goodrive350-pn.xml\", name = \"d-1\", access_point = \"NO_DAP\" },\n]\n\
        [[ethercat]]\ninterface = \"veth1\"\ndevices = [\n\
        { device = \"goodrive350-pn.xml\", modules = [\"X\"] },\n]\n";
    let problems: Vec<String> = match file::parse(text, &eds) {
        Ok(_) => Vec::new(),
        Err(problems) => problems
            .iter()
            .map(|p| format!("{}:{}", p.line, p.message))
            .collect(),
    };
    assert_eq!(
        problems[0],
        "4:EDS708: no access point \"NO_DAP\"; did you mean:\n  \"DAP_GD350_PN\""
    );
    assert_eq!(
        problems[1],
        "9:EDS708: modules are chosen in an ESI file on [[ethercat]]"
    );
}
