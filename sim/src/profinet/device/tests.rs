use super::*;
use crate::drives::pkw_pzd::Bus;
use crate::profinet::ar::config::{RealSlot, RealSubmodule};
use crate::profinet::controller::{connected, response, Controller};
use crate::profinet::wire::rpc::{PnioStatus, Uuid};
use crate::profinet::wire::rt::{RtFrame, DATA_STATUS_GOOD};
use crate::profinet::wire::{append, Ethernet, Mac};

const DEVICE: Mac = [2, 0, 0, 0, 3, 0x50];
const CONTROLLER: Mac = [2, 0, 0, 0, 0, 1];
const FROM: Peer = ([10, 0, 0, 1], 49152);

fn station() -> Station {
    Station {
        mac: DEVICE,
        name_of_station: "dev".to_owned(),
        ip: [[10, 0, 0, 2], [255, 255, 255, 0], [0; 4]],
        vendor_id: 0x0350,
        device_id: 0x0350,
        type_of_station: "t".to_owned(),
        instance: (0, 1),
    }
}

fn card() -> DeviceConfig {
    let read = edsgen_model::read::read_bytes(
        std::path::Path::new("goodrive350-pn.xml"),
        include_bytes!("../../../../eds/goodrive350-pn.xml"),
    );
    DeviceConfig::from_gsdml(read.device.profinet().expect("a GSDML"))
}

/// An IO AR from Connect to data exchange at 0 ms: the controller and the FrameIDs.
fn establish(device: &mut Device, config: &DeviceConfig) -> (Controller, (u16, u16)) {
    let object = Uuid::pnio_object(1, 0x0350, 0x0350);
    let mut ctl = Controller::new(CONTROLLER, object, 3);
    let blocks = ctl.connect_blocks(config, 32, 8, 3);
    let now = Instant::from_millis(0);
    let answer = device.handle_datagram(now, FROM, &ctl.connect(&blocks));
    let (status, args) = response(&answer.expect("an answer")).expect("a response");
    assert_eq!(status, PnioStatus::OK);
    let ids = connected(&args).expect("IOCRs").frame_ids;
    device.handle_datagram(now, FROM, &ctl.prm_end());
    let (_, ready) = device.poll_datagram().expect("ApplicationReady");
    let done = ctl.answer_ready(&ready).expect("a Done");
    assert_eq!(device.handle_datagram(now, FROM, &done), None);
    (ctl, ids)
}

fn output_frame(frame_id: u16, c_sdu: &[u8]) -> Vec<u8> {
    let mut frame = Vec::new();
    append(&mut frame, |b| Ethernet::emit(DEVICE, CONTROLLER, b));
    let rt = RtFrame {
        frame_id,
        c_sdu,
        cycle_counter: 0,
        data_status: DATA_STATUS_GOOD,
        transfer_status: 0,
    };
    append(&mut frame, |b| rt.emit(b));
    frame
}

#[test]
fn a_device_without_a_drive_sends_zero_inputs_with_good_status_only_in_data_exchange() {
    let config = DeviceConfig {
        slots: vec![
            RealSlot {
                slot: 0,
                module_ident: 1,
                submodules: vec![RealSubmodule {
                    subslot: 1,
                    ident: 1,
                    input_len: 0,
                    output_len: 0,
                    records: vec![],
                }],
            },
            RealSlot {
                slot: 1,
                module_ident: 0x20,
                submodules: vec![RealSubmodule {
                    subslot: 1,
                    ident: 0x20,
                    input_len: 4,
                    output_len: 2,
                    records: vec![],
                }],
            },
        ],
        send_clocks: vec![32],
        reduction_ratios: vec![8],
        min_device_interval: 32,
    };
    let mut device = Device::new(station(), config.clone(), None);
    assert_eq!(device.poll_frame(Instant::from_millis(0)), None);
    let (_, (input_id, _)) = establish(&mut device, &config);
    let frame = device
        .poll_frame(Instant::from_millis(0))
        .expect("an input frame");
    assert_eq!(frame[12..16], [0x88, 0x92, 0xC0, 0x01]);
    // Slot 0's IOPS at 0, slot 1's four bytes of zero and IOPS, then slot 1's IOCS.
    assert_eq!(frame[16..23], [0x80, 0, 0, 0, 0, 0x80, 0x80]);
    assert_eq!(input_id, 0xC001);
    // The next one after 8 ms.
    assert_eq!(device.poll_frame(Instant::from_millis(7)), None);
    assert!(device.poll_frame(Instant::from_millis(8)).is_some());
    // The next send is what is due next.
    assert_eq!(device.poll_timeout(), Some(Instant::from_millis(16)));
    // No output frame within the activity timeout (10 s): the watchdog aborts the AR.
    device.handle_timeout(Instant::from_millis(9_999));
    assert!(device.poll_frame(Instant::from_millis(9_999)).is_some());
    device.handle_timeout(Instant::from_millis(10_000));
    let events: Vec<_> = std::iter::from_fn(|| device.poll_event()).collect();
    assert_eq!(events.last(), Some(&DeviceEvent::Ar(ArEvent::Aborted)));
    assert_eq!(device.poll_frame(Instant::from_millis(10_008)), None);
}

#[test]
fn the_card_runs_its_drive_and_record_256_sets_the_received_pzd_meanings() {
    let config = card();
    let drive = PkwPzdDrive::bus_controlled(Bus::Profinet, Instant::from_millis(0));
    let mut device = Device::new(station(), config.clone(), Some(drive));
    let (mut ctl, (_, output_id)) = establish(&mut device, &config);
    // P16.33 (received PZD3) = 1: PZD3 becomes the set frequency too.
    let record: Vec<u8> = [1u16, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0]
        .iter()
        .flat_map(|w| w.to_be_bytes())
        .collect();
    device.handle_datagram(
        Instant::from_millis(1),
        FROM,
        &ctl.write(1, 1, 256, &record),
    );
    assert_eq!(device.drive().and_then(|d| d.parameter(0x1021)), Some(1));
    let (_, read) = response(
        &device
            .handle_datagram(Instant::from_millis(1), FROM, &ctl.read(1, 1, 256))
            .expect("an answer"),
    )
    .expect("a response");
    assert_eq!(read[64..], record[..]);
    // CW 1 and PZD2 300 (3.00 Hz): the drive runs.
    let mut c_sdu = vec![0u8; 40];
    c_sdu[8..12].copy_from_slice(&[0, 1, 0x01, 0x2C]);
    c_sdu[32] = 0x80;
    let mut ms = 0;
    while device.drive().is_some_and(|d| !d.vfd().running()) && ms < 1000 {
        ms += 8;
        let now = Instant::from_millis(ms);
        device.handle_frame(now, &output_frame(output_id, &c_sdu));
        device.handle_timeout(now);
        while device.poll_frame(now).is_some() {}
    }
    assert!(device.drive().is_some_and(|d| d.vfd().running()), "{ms} ms");
    // Release: the drive stays, the cyclic exchange stops.
    device.handle_datagram(Instant::from_millis(ms), FROM, &ctl.release());
    assert!(device.drive().is_some());
    assert_eq!(device.poll_frame(Instant::from_millis(ms + 100)), None);
}

/// A low-priority alarm frame of the controller to the device (its LocalAlarmReference 1,
/// the device's 1).
fn alarm_frame(pdu_type: u8, flags: u8, send: u16, ack: u16, var: &[u8]) -> Vec<u8> {
    use crate::profinet::wire::alarm::{emit_frame, RtaHeader, FRAME_ID_LOW, RTA_VERSION};
    let header = RtaHeader {
        dst: 1,
        src: 1,
        pdu_type,
        version: RTA_VERSION,
        add_flags: flags,
        send_seq: send,
        ack_seq: ack,
    };
    emit_frame(DEVICE, CONTROLLER, 0xA000, FRAME_ID_LOW, &header, var)
}

#[test]
fn a_drive_fault_is_a_diagnosis_alarm_the_controller_acknowledges_and_its_reset_disappears() {
    use crate::profinet::alarm::AlarmEvent;
    use crate::profinet::wire::alarm::*;
    let config = card();
    let drive = PkwPzdDrive::bus_controlled(Bus::Profinet, Instant::from_millis(0));
    let mut device = Device::new(station(), config.clone(), Some(drive));
    let (_, (_, output_id)) = establish(&mut device, &config);
    let mut c_sdu = vec![0u8; 40];
    c_sdu[32] = 0x80;
    let t = Instant::from_millis(8);
    device.handle_frame(t, &output_frame(output_id, &c_sdu));
    while device.poll_event().is_some() {}
    assert!(device.poll_frame(t).is_some(), "the input frame");
    assert_eq!(device.poll_frame(t), None, "no alarm without a fault");

    // Fault type 4 (P07.27's numbering) trips the drive.
    device.inject_fault(t, 4);
    let frame = device.poll_frame(t).expect("the alarm");
    #[rustfmt::skip]
    assert_eq!(
        frame[..72],
        [
            2, 0, 0, 0, 0, 1, 2, 0, 0, 0, 3, 0x50, 0x81, 0x00, 0xA0, 0x00, 0x88, 0x92,
            0xFE, 0x01, 0x00, 0x01, 0x00, 0x01, 0x11, 0x11, 0xFF, 0xFF, 0xFF, 0xFE, 0x00, 0x28,
            0x00, 0x02, 0x00, 0x24, 0x01, 0x00,             // AlarmNotification low
            0x00, 0x01, 0x00, 0x00, 0x00, 0x00,             // Diagnosis, API 0
            0x00, 0x01, 0x00, 0x01,                         // slot 1, subslot 1
            0x00, 0x00, 0x00, 0x10, 0x00, 0x00, 0x00, 0x10, // the GSDML's ident numbers
            0xA8, 0x00,                                     // AR, submodule, channel; seq 0
            0x80, 0x02,                                     // ExtChannelDiagnosis
            0x80, 0x00, 0x08, 0x00, 0x01, 0x01,             // submodule, appears, 0x0101
            0x00, 0x01, 0x00, 0x00, 0x00, 0x04,             // fault type 4
        ]
    );
    // The controller's transport ACK, then its AlarmAck; the device ACKs that.
    let t = Instant::from_millis(10);
    assert_eq!(
        device.handle_frame(t, &alarm_frame(PDU_ACK, 0x01, SEQ_NONE, SEQ_FIRST, &[])),
        None
    );
    let notification = AlarmNotification::parse(&frame[32..72]).expect("a notification");
    let ack = AlarmAck {
        high: false,
        source: notification.source,
        status: PnioStatus::OK,
    };
    let mut var = Vec::new();
    append_ack(&mut var, &ack);
    device.handle_frame(t, &alarm_frame(PDU_DATA, 0x11, SEQ_FIRST, SEQ_FIRST, &var));
    let tack = device.poll_frame(t).expect("the transport ACK");
    assert_eq!(
        tack[24..32],
        [0x13, 0x01, 0xFF, 0xFF, 0xFF, 0xFF, 0x00, 0x00]
    );
    assert_eq!(
        device.poll_event(),
        Some(DeviceEvent::Alarm(AlarmEvent::Acknowledged(ack)))
    );

    // The cause gone, the controller resets the fault (CW command 7): the diagnosis disappears.
    device.remove_fault_cause();
    c_sdu[8..10].copy_from_slice(&[0, 7]);
    let t = Instant::from_millis(16);
    device.handle_frame(t, &output_frame(output_id, &c_sdu));
    assert_eq!(device.drive().and_then(|d| d.vfd().fault()), None);
    let frame = device.poll_frame(t).expect("the disappears alarm");
    assert_eq!(
        frame[26..30],
        [0x00, 0x00, 0xFF, 0xFF],
        "SendSeqNum 0, AckSeqNum 0xFFFF"
    );
    let notification = AlarmNotification::parse(&frame[32..72]).expect("a notification");
    assert_eq!(
        (
            notification.source.alarm_type,
            notification.source.specifier
        ),
        (ALARM_DIAGNOSIS_DISAPPEARS, 0x0801)
    );
    assert_eq!(
        notification.payload,
        Some((
            USI_EXT_CHANNEL_DIAGNOSIS,
            vec![0x80, 0x00, 0x10, 0x00, 0x01, 0x01, 0x00, 0x01, 0x00, 0x00, 0x00, 0x04]
        ))
    );
}

#[test]
fn an_alarm_never_acknowledged_is_repeated_then_the_ar_ends_with_an_err_pdu() {
    use crate::profinet::alarm::AlarmEvent;
    let config = card();
    let drive = PkwPzdDrive::bus_controlled(Bus::Profinet, Instant::from_millis(0));
    let mut device = Device::new(station(), config.clone(), Some(drive));
    establish(&mut device, &config);
    while device.poll_event().is_some() {}
    let t0 = Instant::from_millis(0);
    device.inject_fault(t0, 4);
    let alarm = device.poll_frame(t0).expect("the alarm");
    let mut repeats = 0;
    let mut err = None;
    // RTATimeoutFactor 1 and RTARetries 3 (the controller's AlarmCRBlockReq): 100 ms apart.
    for ms in (1..=40).map(|n| n * 10) {
        let now = Instant::from_millis(ms);
        device.handle_timeout(now);
        while let Some(frame) = device.poll_frame(now) {
            if frame == alarm {
                repeats += 1;
            } else if frame[18..20] == [0xFE, 0x01] {
                err = Some((ms, frame));
            }
        }
    }
    assert_eq!(repeats, 3);
    let (ms, err) = err.expect("an ERR PDU");
    assert_eq!(ms, 400);
    assert_eq!(
        err[24..36],
        [0x14, 0x01, 0xFF, 0xFF, 0xFF, 0xFE, 0x00, 0x04, 0xCF, 0x81, 0xFD, 0x08]
    );
    let events: Vec<_> = std::iter::from_fn(|| device.poll_event()).collect();
    assert_eq!(
        events,
        [
            DeviceEvent::Alarm(AlarmEvent::Aborted(PnioStatus::new(0xCF, 0x81, 0xFD, 0x08))),
            DeviceEvent::Ar(ArEvent::Aborted)
        ]
    );
    assert_eq!(
        device.poll_frame(Instant::from_millis(408)),
        None,
        "no cyclic data"
    );
}
