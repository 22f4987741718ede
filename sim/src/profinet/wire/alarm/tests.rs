use super::*;
use crate::profinet::wire::rpc::PnioStatus;

const CONTROLLER: Mac = [2, 0, 0, 0, 0, 1];
const DEVICE: Mac = [2, 0, 0, 0, 3, 0x50];

fn diagnosis() -> AlarmNotification {
    AlarmNotification {
        high: false,
        source: AlarmSource {
            alarm_type: ALARM_DIAGNOSIS,
            api: 0,
            slot: 1,
            subslot: 1,
            specifier: 3 | SPEC_CHANNEL_DIAGNOSIS | SPEC_SUBMODULE_DIAGNOSIS | SPEC_AR_DIAGNOSIS,
        },
        module_ident: 0x10,
        submodule_ident: 0x10,
        payload: Some((USI_EXT_CHANNEL_DIAGNOSIS, {
            let mut d = Vec::new();
            let diagnosis = ChannelDiagnosis {
                channel: CHANNEL_SUBMODULE,
                properties: CHANNEL_APPEARS,
                error_type: 0x0101,
                ext: Some((1, 4)),
            };
            crate::profinet::wire::append(&mut d, |b| diagnosis.emit(b));
            d
        })),
    }
}

#[test]
fn a_diagnosis_notification_in_a_data_frame_has_these_bytes_and_reads_back() {
    let mut var = Vec::new();
    diagnosis().emit(&mut var);
    #[rustfmt::skip]
    let expected = [
        0x00, 0x02, 0x00, 0x24, 0x01, 0x00, // BlockHeader: low, 36 bytes, 1.0
        0x00, 0x01,                         // AlarmType Diagnosis
        0x00, 0x00, 0x00, 0x00,             // API 0
        0x00, 0x01, 0x00, 0x01,             // slot 1, subslot 1
        0x00, 0x00, 0x00, 0x10,             // ModuleIdentNumber
        0x00, 0x00, 0x00, 0x10,             // SubmoduleIdentNumber
        0xA8, 0x03,                         // AlarmSpecifier: AR, submodule, channel; seq 3
        0x80, 0x02,                         // USI ExtChannelDiagnosis
        0x80, 0x00, 0x08, 0x00, 0x01, 0x01, // channel 0x8000, appears, error type 0x0101
        0x00, 0x01, 0x00, 0x00, 0x00, 0x04, // ExtChannelErrorType 1, AddValue 4
    ];
    assert_eq!(var, expected);
    assert_eq!(AlarmNotification::parse(&var), Some(diagnosis()));

    let header = RtaHeader {
        dst: 0x0003,
        src: 0x0001,
        pdu_type: PDU_DATA,
        version: RTA_VERSION,
        add_flags: WINDOW_1 | TACK,
        send_seq: SEQ_FIRST,
        ack_seq: SEQ_NONE,
    };
    let frame = emit_frame(CONTROLLER, DEVICE, 0xA000, FRAME_ID_LOW, &header, &var);
    assert_eq!(frame.len(), 18 + 2 + 12 + 40);
    #[rustfmt::skip]
    assert_eq!(
        frame[..32],
        [
            2, 0, 0, 0, 0, 1, 2, 0, 0, 0, 3, 0x50,
            0x81, 0x00, 0xA0, 0x00, 0x88, 0x92, // VLAN priority 5, PROFINET
            0xFE, 0x01,                         // FrameID low
            0x00, 0x03, 0x00, 0x01,             // AlarmDstEndpoint, AlarmSrcEndpoint
            0x11, 0x11,                         // DATA version 1; window 1, TACK
            0xFF, 0xFF, 0xFF, 0xFE, 0x00, 0x28, // SendSeqNum, AckSeqNum, VarPartLen 40
        ]
    );
    let read = RtaFrame::parse(&frame).expect("an alarm frame");
    assert_eq!(
        (read.frame_id, read.high(), read.header, read.var_part),
        (FRAME_ID_LOW, false, header, &var[..])
    );
    assert_eq!(read.eth.vlan, Some(0xA000));
}

#[test]
fn an_alarm_ack_has_these_bytes_and_only_a_whole_one_reads() {
    let ack = AlarmAck {
        high: false,
        source: diagnosis().source,
        status: PnioStatus::OK,
    };
    let mut var = Vec::new();
    append_ack(&mut var, &ack);
    #[rustfmt::skip]
    assert_eq!(
        var,
        [
            0x80, 0x02, 0x00, 0x12, 0x01, 0x00,
            0x00, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01, 0x00, 0x01,
            0xA8, 0x03, 0x00, 0x00, 0x00, 0x00,
        ]
    );
    assert_eq!(AlarmAck::parse(&var), Some(ack));
    assert_eq!(AlarmAck::parse(&var[..21]), None);
    // A notification is no AlarmAck, and the other way round.
    assert_eq!(AlarmNotification::parse(&var), None);
    let mut notification = Vec::new();
    diagnosis().emit(&mut notification);
    assert_eq!(AlarmAck::parse(&notification), None);
    // Bytes past the block.
    var.push(0);
    assert_eq!(AlarmAck::parse(&var), None);
}

#[test]
fn frames_too_short_or_of_another_frame_id_are_not_alarm_frames() {
    let header = RtaHeader {
        dst: 1,
        src: 2,
        pdu_type: PDU_ERR,
        version: RTA_VERSION,
        add_flags: WINDOW_1,
        send_seq: 0,
        ack_seq: 0,
    };
    let frame = emit_frame(
        DEVICE,
        CONTROLLER,
        0xC000,
        FRAME_ID_HIGH,
        &header,
        &[0xCF, 0x81, 0xFD, 0x08],
    );
    let read = RtaFrame::parse(&frame).expect("an ERR frame");
    assert!(read.high());
    assert_eq!(
        (read.header.pdu_type, read.var_part),
        (PDU_ERR, &[0xCF, 0x81, 0xFD, 0x08][..])
    );
    // VarPartLen beyond the frame (the frame cut before its padding).
    assert_eq!(RtaFrame::parse(&frame[..35]), None);
    // Header cut short.
    assert_eq!(RtaFrame::parse(&frame[..25]), None);
    let mut other = frame.clone();
    other[18..20].copy_from_slice(&0xC001u16.to_be_bytes());
    assert_eq!(RtaFrame::parse(&other), None);
    let mut other = frame;
    other[16..18].copy_from_slice(&0x0800u16.to_be_bytes());
    assert_eq!(RtaFrame::parse(&other), None);
}
