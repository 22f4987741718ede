//! A modular PROFINET device from the corpus (p-net's IODevice GSDML, whose modules are only
//! `AllowedInSlots`) served with the modules chosen on the command line: the Connect `pn io`
//! builds from the same choice (exact blocks, no root needed); then, over a veth pair joining
//! two private network namespaces, `pn io` and profinet-py (scripts/pn_modules_controller.py)
//! exchange data with it (the device loops its outputs back to its inputs: the 8 DO module's
//! byte comes back in the 8 DI module's), and `pn io` expecting another module in a slot gets
//! the device's ModuleDiffBlock and still exchanges data. Needs the GSDML corpus and, for the
//! wire, root: without them the tests say so and pass, except under `CI=true`.

mod process_support;

use std::path::PathBuf;
use std::time::Duration;

use edsgen_model::model::modules::{choose_pn, parse_choices};
use edsgen_sim::profinet::ar::config::DeviceConfig;
use edsgen_sim::profinet::controller::Controller;
use edsgen_sim::profinet::wire::blocks::{split, EXPECTED_SUBMODULE_BLOCK_REQ, IOCR_BLOCK_REQ};
use edsgen_sim::profinet::wire::rpc::Uuid;
use process_support::netns::{is_root, VethPair};
use process_support::{gsdml_corpus_dir, python, skip, Process, EDSGEN};

/// p-net's IODevice: IDM_11 8 DI (ModuleIdentNumber 0x30), IDM_12 8 DO (0x31), IDM_13 8 DI
/// and 8 DO (0x32), each allowed in slots 1 to 4, none used by default.
const IODEVICE: &str = "rtlabs-com__p-net/GSDML-V2.4-rtlabs-IODevice-20201211.xml";

fn iodevice() -> Option<PathBuf> {
    Some(gsdml_corpus_dir()?.join(IODEVICE))
}

/// A slot: its number, ModuleIdentNumber, and (subslot, ident, input and output bytes) each.
type Slot = (u16, u32, Vec<(u16, u32, u16, u16)>);

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

#[test]
fn pn_io_connects_with_the_modules_chosen() {
    let Some(path) = iodevice() else { return };
    let read = edsgen_model::load::load(&path, None).expect("the GSDML loads");
    let pn = read.device.profinet().expect("a GSDML");
    // Nothing is used by default: the access point alone, no IO data.
    assert_eq!(DeviceConfig::from_gsdml(pn).slots.len(), 1);
    let choices = parse_choices(&["1=IDM_12", "IDM_11"]).expect("two choices");
    let chosen = choose_pn(pn, None, &choices).expect("allowed");
    let config = DeviceConfig::configured(pn, &chosen);
    let slots: Vec<Slot> = config
        .slots
        .iter()
        .map(|s| {
            let subs = s.submodules.iter();
            let subs = subs.map(|b| (b.subslot, b.ident, b.input_len, b.output_len));
            (s.slot, s.module_ident, subs.collect())
        })
        .collect();
    assert_eq!(
        slots,
        [
            (
                0,
                1,
                vec![(1, 1, 0, 0), (0x8000, 0x8000, 0, 0), (0x8001, 0x8001, 0, 0)]
            ),
            (1, 0x31, vec![(1, 1, 0, 1)]),
            (2, 0x30, vec![(1, 1, 1, 0)]),
        ]
    );
    let ctl = Controller::new([2, 0, 0, 0, 0, 1], Uuid([7; 16]), 1);
    let blocks = ctl.connect_blocks(&config, 32, 8, 125);
    let blocks = split(&blocks).expect("blocks");
    let iocrs: Vec<String> = blocks
        .iter()
        .filter(|b| b.block_type == IOCR_BLOCK_REQ)
        .map(|b| hex(b.body))
        .collect();
    let expected: Vec<String> = blocks
        .iter()
        .filter(|b| b.block_type == EXPECTED_SUBMODULE_BLOCK_REQ)
        .map(|b| hex(b.body))
        .collect();
    // Input CR: IOCRType 1, reference 1, LT 0x8892, RT_CLASS_1, DataLength 40, FrameID 0xC001,
    // SendClockFactor 32, ReductionRatio 8, phase 1, sequence 0, FrameSendOffset best
    // effort, watchdog and data hold 125, VLAN tag 0xC000, no multicast MAC; API 0 with four
    // IO data objects (the access point's three submodules without data, offsets 0 to 2, and
    // the 8 DI module's byte at 3, its IOPS at 4) and one IOCS (the 8 DO module's, at 5).
    // Output CR: type 2, reference 2, FrameID chosen by the device; the 8 DO module's byte at
    // 0 (IOPS at 1), the IOCS of the four others at 2 to 5.
    assert_eq!(
        iocrs,
        [
            "000100018892000000010028c0010020000800010000ffffffff007d007dc000000000000000\
             0001000000000004000000010000000080000001000080010002000200010003\
             0001000100010005",
            "000200028892000000010028ffff0020000800010000ffffffff007d007dc000000000000000\
             0001000000000001000100010000000400000001000200008000000300008001\
             0004000200010005",
        ]
    );
    // Three API entries (one per slot), API 0 each: slot 0, the access point (0x1) with its
    // three submodules without data (one input DataDescription of length 0, IOCS and IOPS 1
    // byte); slot 1, 0x31, submodule 1 (0x1) of type output, 1 byte; slot 2, 0x30, submodule 1
    // of type input, 1 byte.
    assert_eq!(
        expected,
        ["0003\
          00000000000000000001000000030001000000010000000100000101\
          800000008000000000010000010180010000800100000001000001010000\
          000000010000003100000001000100000001000200020001010100000000\
          000200000030000000010001000000010001000100010101"]
    );
}

impl VethPair {
    /// `edsgen simulate --profinet` in namespace 0 with the IODevice and `modules`, once it
    /// has said where it is.
    fn device(&self, gsdml: &str, modules: &[&str]) -> Process {
        let mut args = vec!["simulate", "--profinet", &self.device_if, gsdml];
        for module in modules {
            args.extend(["--module", module]);
        }
        let device = Process::start(self.inside(0, EDSGEN).args(args));
        assert_eq!(
            device
                .stdout_line(
                    |l| l.starts_with("PROFINET device"),
                    Duration::from_secs(10)
                )
                .split(" on ")
                .next(),
            Some("PROFINET device `rt-labs-dev` (VendorID 0xfeed, DeviceID 0xbeef)")
        );
        device
    }

    /// `pn io` in namespace 1 for 100 cycles with `args` after the GSDML.
    fn pn_io(&self, gsdml: &str, args: &[&str]) -> Vec<String> {
        let mut all = vec!["pn", "io", &self.master_if, "rt-labs-dev", "--gsdml", gsdml];
        all.extend(["--cycles", "100"]);
        all.extend(args);
        let done = Process::start(self.inside(1, EDSGEN).args(all)).finish(Duration::from_secs(30));
        assert_eq!(done.code, Some(0), "{}\n{}", done.stdout, done.stderr);
        // The first line names the device's MAC, which the interface's gives.
        done.stdout.lines().skip(1).map(str::to_owned).collect()
    }
}

fn wire() -> Option<(String, VethPair)> {
    if !is_root() {
        skip::<()>("not root: no network namespaces or raw sockets for PROFINET");
        return None;
    }
    let gsdml = iodevice()?.to_str().expect("a UTF-8 path").to_owned();
    Some((
        gsdml,
        VethPair::new("pn-mod", &["10.81.0.2/24"], &["10.81.0.1/24"]),
    ))
}

#[test]
fn pn_io_and_profinet_py_exchange_data_with_the_modules_chosen() {
    let Some((gsdml, net)) = wire() else { return };
    let Some(python) = python() else { return };
    let mut device = net.device(&gsdml, &["1=IDM_12", "IDM_11"]);
    let mut said = net.pn_io(
        &gsdml,
        &["--module", "1=IDM_12", "--module", "IDM_11", "1.1=a5"],
    );
    // The first input frames may come before the first output frame has looped back.
    said.retain(|l| l != "inputs 2.1: Input 8 bits=0x00");
    assert_eq!(
        said,
        [
            "connected: input frame 0xc001, output frame 0xc102, every 8 ms",
            "application ready: exchanging data",
            "inputs 2.1: Input 8 bits=0xa5",
            "released the AR after 100 cycles",
        ]
    );
    let script = process_support::root().join("scripts/pn_modules_controller.py");
    let controller = Process::start(
        net.inside(1, python.to_str().expect("a UTF-8 path"))
            .arg(script)
            .args([&net.master_if, "rt-labs-dev", &gsdml, "1", "2", "3c"]),
    );
    let done = controller.finish(Duration::from_secs(60));
    assert_eq!(done.code, Some(0), "{}\n{}", done.stdout, done.stderr);
    let lines: Vec<&str> = done.stdout.lines().collect();
    // profinet-py reads the modules from the device's RealIdentificationData, takes their IO
    // lengths from the GSDML and sees its output byte come back in the 8 DI module's input.
    assert_eq!(
        lines,
        [
            "found rt-labs-dev at 10.81.0.2",
            "modules 1=0x31 2=0x30",
            "io 1.1=0/1 2.1=1/0",
            "connected input 0xc001 output 0xc102",
            "application ready",
            "output 1.1=3c input 2.1=3c",
            "released",
        ]
    );
    device.close_stdin();
}

#[test]
fn a_controller_expecting_another_module_gets_the_module_diff() {
    let Some((gsdml, net)) = wire() else { return };
    let device = net.device(&gsdml, &["1=IDM_12", "IDM_11"]);
    // Slot 2 holds the 8 DI module; the controller expects the 8 DI 8 DO one there.
    let mut said = net.pn_io(
        &gsdml,
        &["--module", "1=IDM_12", "--module", "2=IDM_13", "1.1=5a"],
    );
    said.retain(|l| l != "inputs 2.1: Input 8 bits=0x00");
    // The module really in slot 2 (0x30), wrong (1); its submodule wrong (IdentInfo 2, with
    // the format indicator: 0x9000). The AR is still established, the wrong module not
    // parametrized, and the data exchanged as the controller expects it.
    assert_eq!(
        said,
        [
            "the device's modules differ from the configuration (its ModuleDiffBlock):",
            "  API 0 slot 2: ModuleIdentNumber 0x00000030, ModuleState 1 (wrong module)",
            "    subslot 0x0001: SubmoduleIdentNumber 0x00000001, SubmoduleState 0x9000 (wrong)",
            "connected: input frame 0xc001, output frame 0xc102, every 8 ms",
            "not writing record 123 of slot 2 subslot 1: the device has another submodule there",
            "not writing record 124 of slot 2 subslot 1: the device has another submodule there",
            "application ready: exchanging data",
            "inputs 2.1: Input 8 bits=0x5a",
            "released the AR after 100 cycles",
        ]
    );
    assert_eq!(
        device.stdout_line(|l| l.starts_with("AR connected"), Duration::from_secs(5)),
        "AR connected (ARType 0x0001): input FrameID 0xc001, output FrameID 0xc102, \
         every 8000 us, with module differences"
    );
}
