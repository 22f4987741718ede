//! A Connect request checked against the device's configuration: its blocks (one ARBlockReq;
//! for an IO AR an input and an output IOCRBlockReq, one AlarmCRBlockReq and the
//! ExpectedSubmoduleBlockReqs), each field the device cannot serve refused with the PNIOStatus
//! IEC 61158-6-10 gives it (ErrorCode 0xDB, ErrorDecode 0x81 PNIO, ErrorCode1 the faulty block,
//! ErrorCode2 the faulty field's number in it, as p-net numbers them), the expected submodules
//! compared with the real ones (differences go in the ModuleDiffBlock, as PROFINET answers
//! them: the AR is still established), and the cyclic layout the IOCRs give.

use super::super::cyclic::{CrLayout, DataObject};
use super::super::wire::blocks::*;
use super::super::wire::rpc::PnioStatus;
use super::super::wire::rt::RT_CLASS_1;
use super::super::wire::Mac;
use super::config::DeviceConfig;
use edsgen_runtime::Duration;

/// ARType IOCARSingle (an IO controller's AR with cyclic data).
pub const AR_TYPE_IOC_SINGLE: u16 = 0x0001;
/// ARType IOSAR (a supervisor's device access AR, records only).
pub const AR_TYPE_IOSAR: u16 = 0x0006;

/// ErrorCode1 of a faulty ARBlockReq.
const FAULTY_AR: u8 = 0x01;
/// ErrorCode1 of a faulty IOCRBlockReq.
const FAULTY_IOCR: u8 = 0x02;
/// ErrorCode1 of a faulty ExpectedSubmoduleBlockReq.
const FAULTY_EXPECTED: u8 = 0x03;
/// ErrorCode1 of a faulty AlarmCRBlockReq.
const FAULTY_ALARM: u8 = 0x04;
/// ErrorCode1 CMRPC (the request as a whole).
pub const CMRPC: u8 = 0x40;
/// CMRPC: an unknown block.
const CMRPC_UNKNOWN_BLOCKS: u8 = 0x01;
/// CMRPC: an IOCR missing.
const CMRPC_IOCR_MISSING: u8 = 0x02;
/// CMRPC: a block missing or twice.
const CMRPC_WRONG_BLOCK_COUNT: u8 = 0x03;

/// A refusal of a Connect.
pub fn refuse(code1: u8, code2: u8) -> PnioStatus {
    PnioStatus::new(
        PnioStatus::CODE_CONNECT,
        PnioStatus::DECODE_PNIO,
        code1,
        code2,
    )
}

/// What an accepted Connect established.
#[derive(Debug, Clone, PartialEq)]
pub struct Accepted {
    /// The ARBlockReq.
    pub ar: ArBlockReq,
    /// The IOCR answers (type, reference, FrameID).
    pub iocrs: Vec<IocrBlockRes>,
    /// The AlarmCR, if the controller asked for one.
    pub alarm: Option<AlarmCrBlockReq>,
    /// The differences from the expected configuration.
    pub diff: Vec<ApiIdent>,
    /// The cyclic layout (an IO AR).
    pub layout: Option<CrLayout>,
}

/// Checks a Connect's `args` from a controller for a device with `config` and `mac`.
pub fn check(config: &DeviceConfig, mac: Mac, args: &[u8]) -> Result<Accepted, PnioStatus> {
    let blocks = split(args).map_err(|_| refuse(CMRPC, CMRPC_UNKNOWN_BLOCKS))?;
    let mut ar = None;
    let mut iocrs = Vec::new();
    let mut alarm = None;
    let mut expected = Vec::new();
    for block in &blocks {
        match block.block_type {
            AR_BLOCK_REQ if ar.is_none() => {
                ar = Some(ArBlockReq::parse(block.body).ok_or(refuse(FAULTY_AR, 1))?)
            }
            IOCR_BLOCK_REQ => {
                iocrs.push(IocrBlockReq::parse(block.body).ok_or(refuse(FAULTY_IOCR, 1))?)
            }
            ALARM_CR_BLOCK_REQ if alarm.is_none() => {
                alarm = Some(AlarmCrBlockReq::parse(block.body).ok_or(refuse(FAULTY_ALARM, 1))?)
            }
            EXPECTED_SUBMODULE_BLOCK_REQ => expected.extend(
                ExpectedSubmoduleBlockReq::parse(block.body)
                    .ok_or(refuse(FAULTY_EXPECTED, 1))?
                    .slots,
            ),
            AR_BLOCK_REQ | ALARM_CR_BLOCK_REQ => {
                return Err(refuse(CMRPC, CMRPC_WRONG_BLOCK_COUNT))
            }
            _ => return Err(refuse(CMRPC, CMRPC_UNKNOWN_BLOCKS)),
        }
    }
    let ar = ar.ok_or(refuse(CMRPC, CMRPC_WRONG_BLOCK_COUNT))?;
    // The nil UUID names no AR.
    if ar.ar_uuid.0 == [0; 16] {
        return Err(refuse(FAULTY_AR, 5));
    }
    // CMInitiatorActivityTimeoutFactor: 1 to 1000 (100 ms to 100 s); a larger one would keep
    // an AR that never reaches data exchange (and the device) busy for up to 109 minutes.
    if !(1..=1000).contains(&ar.timeout_factor) {
        return Err(refuse(FAULTY_AR, 10));
    }
    match ar.ar_type {
        AR_TYPE_IOSAR => {
            if !iocrs.is_empty() || !expected.is_empty() {
                return Err(refuse(CMRPC, CMRPC_WRONG_BLOCK_COUNT));
            }
            return Ok(Accepted {
                ar,
                iocrs: Vec::new(),
                alarm,
                diff: Vec::new(),
                layout: None,
            });
        }
        AR_TYPE_IOC_SINGLE => {}
        _ => return Err(refuse(FAULTY_AR, 4)),
    }
    let input = iocrs.iter().filter(|i| i.iocr_type == IOCR_INPUT).count();
    let output = iocrs.iter().filter(|i| i.iocr_type == IOCR_OUTPUT).count();
    if input != 1 || output != 1 || iocrs.len() != 2 {
        return Err(refuse(CMRPC, CMRPC_IOCR_MISSING));
    }
    let alarm = alarm.ok_or(refuse(CMRPC, CMRPC_WRONG_BLOCK_COUNT))?;
    if alarm.alarm_cr_type != 1 {
        return Err(refuse(FAULTY_ALARM, 4));
    }
    if alarm.lt != 0x8892 && alarm.properties & 2 == 0 {
        return Err(refuse(FAULTY_ALARM, 5));
    }
    if !(200..=1432).contains(&alarm.max_alarm_data_length) {
        return Err(refuse(FAULTY_ALARM, 10));
    }
    if expected.is_empty() {
        return Err(refuse(CMRPC, CMRPC_WRONG_BLOCK_COUNT));
    }
    for iocr in &iocrs {
        check_iocr(config, iocr)?;
    }
    let diff = compare(config, &expected);
    let input = iocrs
        .iter()
        .find(|i| i.iocr_type == IOCR_INPUT)
        .ok_or(refuse(CMRPC, 2))?;
    let output = iocrs
        .iter()
        .find(|i| i.iocr_type == IOCR_OUTPUT)
        .ok_or(refuse(CMRPC, 2))?;
    let input_frame_id = if input.frame_id == 0xFFFF {
        0xC000 | input.reference
    } else {
        input.frame_id
    };
    // The device chooses the FrameID it consumes, unlike the input's.
    let output_frame_id = if output.frame_id == 0xFFFF || output.frame_id == input_frame_id {
        0xC100 | (output.reference & 0xFF)
    } else {
        output.frame_id
    };
    let layout = layout(
        &expected,
        input,
        output,
        ar.initiator_mac,
        mac,
        (input_frame_id, output_frame_id),
    )?;
    Ok(Accepted {
        iocrs: vec![
            IocrBlockRes {
                iocr_type: IOCR_INPUT,
                reference: input.reference,
                frame_id: input_frame_id,
            },
            IocrBlockRes {
                iocr_type: IOCR_OUTPUT,
                reference: output.reference,
                frame_id: output_frame_id,
            },
        ],
        ar,
        alarm: Some(alarm),
        diff,
        layout: Some(layout),
    })
}

/// The fields of an IOCRBlockReq the device checks (numbered as p-net numbers them).
fn check_iocr(config: &DeviceConfig, iocr: &IocrBlockReq) -> Result<(), PnioStatus> {
    let err = |field| Err(refuse(FAULTY_IOCR, field));
    if iocr.lt != 0x8892 {
        return err(6);
    }
    if iocr.properties & 0x0F != 1 {
        return err(7);
    }
    if !(40..=1440).contains(&iocr.data_length) {
        return err(8);
    }
    if iocr.frame_id != 0xFFFF && !RT_CLASS_1.contains(&iocr.frame_id) {
        return err(9);
    }
    if !config.send_clocks.contains(&iocr.send_clock_factor) {
        return err(10);
    }
    if !config.reduction_ratios.contains(&iocr.reduction_ratio) {
        return err(11);
    }
    let interval = u32::from(iocr.send_clock_factor) * u32::from(iocr.reduction_ratio);
    if interval < config.min_device_interval {
        return err(11);
    }
    if iocr.phase == 0 || iocr.phase > iocr.reduction_ratio {
        return err(12);
    }
    if !(1..=0x1E00).contains(&iocr.watchdog_factor) {
        return err(15);
    }
    if !(1..=0x1E00).contains(&iocr.data_hold_factor) {
        return err(16);
    }
    if iocr.apis.iter().any(|a| a.api != 0) {
        return err(20);
    }
    Ok(())
}

/// The submodule of `expected` in `slot`, `subslot` and its data length in `direction`.
fn expected_len(expected: &[ExpectedSlot], slot: u16, subslot: u16, direction: u16) -> Option<u16> {
    let sub = expected
        .iter()
        .filter(|s| s.slot == slot)
        .flat_map(|s| &s.submodules)
        .find(|s| s.subslot == subslot)?;
    let len = sub
        .data
        .iter()
        .find(|d| d.direction == direction)
        .map_or(0, |d| d.length);
    Some(len)
}

/// The cyclic layout of the two IOCRs: each IO data object with its expected length, each
/// inside DataLength and apart from the others.
fn layout(
    expected: &[ExpectedSlot],
    input: &IocrBlockReq,
    output: &IocrBlockReq,
    controller: Mac,
    device: Mac,
    (input_frame_id, output_frame_id): (u16, u16),
) -> Result<CrLayout, PnioStatus> {
    let objects = |iocr: &IocrBlockReq,
                   direction: u16|
     -> Result<(Vec<DataObject>, Vec<usize>), PnioStatus> {
        let mut used = vec![false; usize::from(iocr.data_length)];
        let mut claim = |at: usize, len: usize| -> Result<(), PnioStatus> {
            let area = used.get_mut(at..at + len).ok_or(refuse(FAULTY_IOCR, 8))?;
            if area.iter().any(|u| *u) {
                return Err(refuse(FAULTY_IOCR, 22));
            }
            area.fill(true);
            Ok(())
        };
        let mut data = Vec::new();
        let mut iocs = Vec::new();
        for api in &iocr.apis {
            for e in &api.data {
                let len = expected_len(expected, e.slot, e.subslot, direction)
                    .ok_or(refuse(FAULTY_IOCR, 21))?;
                claim(usize::from(e.offset), usize::from(len) + 1)?;
                data.push(DataObject {
                    slot: e.slot,
                    subslot: e.subslot,
                    offset: usize::from(e.offset),
                    len: usize::from(len),
                });
            }
            for e in &api.iocs {
                expected_len(expected, e.slot, e.subslot, direction)
                    .ok_or(refuse(FAULTY_IOCR, 23))?;
                claim(usize::from(e.offset), 1)?;
                iocs.push(usize::from(e.offset));
            }
        }
        Ok((data, iocs))
    };
    let (inputs, input_iocs) = objects(input, DATA_INPUT)?;
    let (outputs, _) = objects(output, DATA_OUTPUT)?;
    let units = u64::from(output.send_clock_factor) * u64::from(output.reduction_ratio);
    Ok(CrLayout {
        controller,
        device,
        output_frame_id,
        output_len: usize::from(output.data_length),
        outputs,
        input_frame_id,
        input_len: usize::from(input.data_length),
        inputs,
        input_iocs,
        // 31.25 µs units.
        interval: Duration::from_micros(units * 3125 / 100),
        watchdog_factor: output.data_hold_factor,
    })
}

/// The expected configuration against the real one: a module that differs (ModuleState
/// wrong module or no module) with all its expected submodules, and in a proper module each
/// submodule that differs (wrong, or no submodule; a data length other than the GSDML's counts
/// as wrong).
pub fn compare(config: &DeviceConfig, expected: &[ExpectedSlot]) -> Vec<ApiIdent> {
    let mut modules: Vec<SlotIdent> = Vec::new();
    for exp in expected {
        let real = config.slot(exp.slot);
        let (state, ident) = match real {
            None => (MODULE_NO, 0),
            Some(r) if r.module_ident != exp.module_ident => (MODULE_WRONG, r.module_ident),
            Some(r) => (MODULE_PROPER, r.module_ident),
        };
        let mut submodules = Vec::new();
        for sub in &exp.submodules {
            let found = real.and_then(|r| r.submodules.iter().find(|s| s.subslot == sub.subslot));
            let sub_state = match found {
                None => SUBMODULE_NO,
                Some(_) if state != MODULE_PROPER => SUBMODULE_WRONG,
                Some(f) => {
                    let lens = |dir| {
                        sub.data
                            .iter()
                            .find(|d| d.direction == dir)
                            .map_or(0, |d| d.length)
                    };
                    if f.ident != sub.ident
                        || lens(DATA_INPUT) != f.input_len
                        || lens(DATA_OUTPUT) != f.output_len
                    {
                        SUBMODULE_WRONG
                    } else {
                        continue;
                    }
                }
            };
            submodules.push((sub.subslot, found.map_or(0, |f| f.ident), sub_state));
        }
        if state != MODULE_PROPER || !submodules.is_empty() {
            match modules.iter_mut().find(|m| m.slot == exp.slot) {
                Some(m) => m.submodules.extend(submodules),
                None => modules.push(SlotIdent {
                    slot: exp.slot,
                    module_ident: ident,
                    state,
                    submodules,
                }),
            }
        }
    }
    if modules.is_empty() {
        Vec::new()
    } else {
        vec![ApiIdent { api: 0, modules }]
    }
}
