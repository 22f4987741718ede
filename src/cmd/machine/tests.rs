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
