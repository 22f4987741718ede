//! The AlarmCR against a controller built by hand: each frame it sends is written here.

use super::*;

const CONTROLLER: Mac = [2, 0, 0, 0, 0, 1];
const DEVICE: Mac = [2, 0, 0, 0, 3, 0x50];
/// The controller's LocalAlarmReference, and the device's.
const CONTROLLER_REF: u16 = 3;
const DEVICE_REF: u16 = 1;

fn request() -> AlarmCrBlockReq {
    AlarmCrBlockReq {
        alarm_cr_type: 1,
        lt: 0x8892,
        properties: 0,
        rta_timeout_factor: 1,
        rta_retries: 3,
        local_alarm_reference: CONTROLLER_REF,
        max_alarm_data_length: 200,
        tag_header_high: 0xC000,
        tag_header_low: 0xA000,
    }
}

fn cr() -> AlarmCr {
    AlarmCr::new(&request(), DEVICE_REF, DEVICE, CONTROLLER)
}

fn alarm(alarm_type: u16) -> AlarmNotification {
    AlarmNotification {
        high: false,
        source: AlarmSource {
            alarm_type,
            api: 0,
            slot: 1,
            subslot: 1,
            specifier: SPEC_CHANNEL_DIAGNOSIS,
        },
        module_ident: 0x10,
        submodule_ident: 0x10,
        payload: Some((
            USI_CHANNEL_DIAGNOSIS,
            vec![0x80, 0x00, 0x08, 0x00, 0x01, 0x01],
        )),
    }
}

/// A low-priority frame of the controller.
fn from_controller(pdu_type: u8, flags: u8, send: u16, ack: u16, var: &[u8]) -> Vec<u8> {
    let header = RtaHeader {
        dst: DEVICE_REF,
        src: CONTROLLER_REF,
        pdu_type,
        version: RTA_VERSION,
        add_flags: flags,
        send_seq: send,
        ack_seq: ack,
    };
    emit_frame(DEVICE, CONTROLLER, 0xA000, FRAME_ID_LOW, &header, var)
}

/// The AlarmAck the controller sends for a low-priority alarm.
fn alarm_ack(alarm_type: u16, sequence: u16) -> Vec<u8> {
    let mut var = Vec::new();
    let ack = AlarmAck {
        high: false,
        source: AlarmSource {
            alarm_type,
            api: 0,
            slot: 1,
            subslot: 1,
            specifier: SPEC_CHANNEL_DIAGNOSIS | sequence,
        },
        status: PnioStatus::OK,
    };
    append_ack(&mut var, &ack);
    var
}

/// The RTA header fields of a frame the device sent: (FrameID, PDUType byte, AddFlags,
/// SendSeqNum, AckSeqNum) and the variable part.
fn sent(frame: &[u8]) -> ((u16, u8, u8, u16, u16), Vec<u8>) {
    let rta = RtaFrame::parse(frame).expect("an alarm frame");
    assert_eq!(rta.eth.vlan, Some(0xA000), "low priority: VLAN priority 5");
    assert_eq!((rta.eth.dst, rta.eth.src), (CONTROLLER, DEVICE));
    assert_eq!(
        (rta.header.dst, rta.header.src),
        (CONTROLLER_REF, DEVICE_REF)
    );
    let h = rta.header;
    (
        (
            rta.frame_id,
            (h.version << 4) | h.pdu_type,
            h.add_flags,
            h.send_seq,
            h.ack_seq,
        ),
        rta.var_part.to_vec(),
    )
}

#[test]
fn an_alarm_is_acknowledged_at_both_layers_and_the_next_one_follows() {
    let mut cr = cr();
    let t0 = Instant::from_millis(1000);
    cr.send(t0, alarm(ALARM_DIAGNOSIS));
    cr.send(t0, alarm(ALARM_DIAGNOSIS_DISAPPEARS));
    let frame = cr.poll_frame().expect("the first alarm");
    assert_eq!(cr.poll_frame(), None, "one alarm at a time");
    #[rustfmt::skip]
    assert_eq!(
        frame[..60],
        [
            2, 0, 0, 0, 0, 1, 2, 0, 0, 0, 3, 0x50, 0x81, 0x00, 0xA0, 0x00, 0x88, 0x92,
            0xFE, 0x01, 0x00, 0x03, 0x00, 0x01, 0x11, 0x11, 0xFF, 0xFF, 0xFF, 0xFE, 0x00, 0x22,
            0x00, 0x02, 0x00, 0x1E, 0x01, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00,
            0x00, 0x01, 0x00, 0x01, 0x00, 0x00, 0x00, 0x10, 0x00, 0x00, 0x00, 0x10,
            0x08, 0x00, 0x80, 0x00,
        ]
    );
    assert_eq!(frame[60..], [0x80, 0x00, 0x08, 0x00, 0x01, 0x01]);
    assert_eq!(cr.poll_timeout(), Some(t0 + Duration::from_millis(100)));

    // The controller's transport ACK of the DATA: no retransmission any more.
    let t1 = t0 + Duration::from_millis(5);
    assert!(cr.handle_frame(
        t1,
        &from_controller(PDU_ACK, WINDOW_1, SEQ_NONE, SEQ_FIRST, &[])
    ));
    assert_eq!(cr.poll_timeout(), None);
    assert_eq!(
        cr.poll_frame(),
        None,
        "the second alarm waits for the AlarmAck"
    );

    // The AlarmAck, a DATA of the controller's: the device ACKs it at the transport layer.
    let t2 = t1 + Duration::from_millis(5);
    let ack = alarm_ack(ALARM_DIAGNOSIS, 0);
    let data = from_controller(PDU_DATA, WINDOW_1 | TACK, SEQ_FIRST, SEQ_FIRST, &ack);
    assert!(cr.handle_frame(t2, &data));
    let tack = cr.poll_frame().expect("the transport ACK");
    assert_eq!(
        sent(&tack),
        ((FRAME_ID_LOW, 0x13, 0x01, 0xFFFF, 0xFFFF), vec![])
    );
    assert_eq!(tack.len(), 60);
    assert_eq!(
        cr.poll_event(),
        Some(AlarmEvent::Acknowledged(
            AlarmAck::parse(&ack).expect("an AlarmAck")
        ))
    );

    // The second alarm: sequence number 1, SendSeqNum 0, acknowledging the AlarmAck's DATA.
    let (header, var) = sent(&cr.poll_frame().expect("the second alarm"));
    assert_eq!(header, (FRAME_ID_LOW, 0x11, 0x11, 0x0000, 0xFFFF));
    let second = AlarmNotification::parse(&var).expect("a notification");
    assert_eq!(
        (second.source.alarm_type, second.source.specifier),
        (ALARM_DIAGNOSIS_DISAPPEARS, SPEC_CHANNEL_DIAGNOSIS | 1)
    );
    // Its ACK comes piggybacked on the AlarmAck's DATA.
    let ack = alarm_ack(ALARM_DIAGNOSIS_DISAPPEARS, 1);
    let data = from_controller(PDU_DATA, WINDOW_1 | TACK, 0x0000, 0x0000, &ack);
    assert!(cr.handle_frame(t2, &data));
    assert_eq!(cr.poll_timeout(), None);
    let (header, _) = sent(&cr.poll_frame().expect("the transport ACK"));
    assert_eq!(header, (FRAME_ID_LOW, 0x13, 0x01, 0x0000, 0x0000));
    assert!(matches!(cr.poll_event(), Some(AlarmEvent::Acknowledged(_))));
    assert_eq!(
        (cr.poll_frame(), cr.poll_event(), cr.closed()),
        (None, None, false)
    );
}

#[test]
fn an_unacknowledged_alarm_is_sent_rta_retries_times_more_then_the_ar_ends_with_err() {
    let mut cr = cr();
    let t0 = Instant::from_millis(0);
    cr.send(t0, alarm(ALARM_DIAGNOSIS));
    let first = cr.poll_frame().expect("the alarm");
    cr.handle_timeout(Instant::from_millis(99));
    assert_eq!(cr.poll_frame(), None);
    for n in 1..=3u64 {
        assert_eq!(cr.poll_timeout(), Some(Instant::from_millis(100 * n)));
        cr.handle_timeout(Instant::from_millis(100 * n));
        assert_eq!(cr.poll_frame().as_ref(), Some(&first), "retransmission {n}");
    }
    assert_eq!(cr.poll_event(), None);
    cr.handle_timeout(Instant::from_millis(400));
    let err = cr.poll_frame().expect("the ERR PDU");
    assert_eq!(
        sent(&err),
        (
            (FRAME_ID_LOW, 0x14, 0x01, 0xFFFF, 0xFFFE),
            vec![0xCF, 0x81, 0xFD, 0x08]
        )
    );
    assert_eq!(
        cr.poll_event(),
        Some(AlarmEvent::Aborted(PnioStatus::new(0xCF, 0x81, 0xFD, 0x08)))
    );
    assert!(cr.closed());
    assert_eq!(cr.poll_timeout(), None);
    cr.send(t0, alarm(ALARM_DIAGNOSIS));
    assert_eq!(cr.poll_frame(), None, "a closed AlarmCR sends nothing");
}

#[test]
fn an_err_pdu_of_the_controller_ends_the_alarm_cr() {
    let mut cr = cr();
    let t0 = Instant::from_millis(0);
    cr.send(t0, alarm(ALARM_DIAGNOSIS));
    cr.poll_frame().expect("the alarm");
    // An ERR with a VarPartLen other than a PNIOStatus's is ignored.
    let short = from_controller(PDU_ERR, WINDOW_1, SEQ_NONE, SEQ_NONE, &[0xCF, 0x81, 0xFD]);
    assert!(cr.handle_frame(t0, &short));
    assert_eq!(cr.poll_event(), None);
    let err = from_controller(
        PDU_ERR,
        WINDOW_1,
        SEQ_NONE,
        SEQ_NONE,
        &[0xCF, 0x81, 0xFD, 0x05],
    );
    assert!(cr.handle_frame(t0, &err));
    assert_eq!(
        cr.poll_event(),
        Some(AlarmEvent::Aborted(PnioStatus::new(0xCF, 0x81, 0xFD, 0x05)))
    );
    assert_eq!((cr.poll_frame(), cr.poll_timeout()), (None, None));
}

#[test]
fn data_out_of_sequence_gets_a_nack_a_repeated_one_its_ack_and_a_strange_block_an_err() {
    let mut cr = cr();
    let t0 = Instant::from_millis(0);
    cr.send(t0, alarm(ALARM_DIAGNOSIS));
    cr.poll_frame().expect("the alarm");
    let ack = alarm_ack(ALARM_DIAGNOSIS, 0);
    // SendSeqNum 5 where 0xFFFF is expected.
    cr.handle_frame(t0, &from_controller(PDU_DATA, 0x11, 5, SEQ_FIRST, &ack));
    let (header, _) = sent(&cr.poll_frame().expect("a NACK"));
    assert_eq!(header, (FRAME_ID_LOW, 0x12, 0x01, 0xFFFE, 0xFFFE));
    assert_eq!(cr.poll_event(), None);
    // Without TACK a DATA is ignored.
    cr.handle_frame(
        t0,
        &from_controller(PDU_DATA, 0x01, SEQ_FIRST, SEQ_FIRST, &ack),
    );
    assert_eq!((cr.poll_frame(), cr.poll_event()), (None, None));
    // In sequence, then again.
    let data = from_controller(PDU_DATA, 0x11, SEQ_FIRST, SEQ_FIRST, &ack);
    cr.handle_frame(t0, &data);
    let first_ack = cr.poll_frame().expect("the ACK");
    assert!(matches!(cr.poll_event(), Some(AlarmEvent::Acknowledged(_))));
    cr.handle_frame(t0, &data);
    assert_eq!(cr.poll_frame(), Some(first_ack), "the same ACK again");
    assert_eq!(cr.poll_event(), None, "acknowledged once");
    // The next DATA in sequence carries a block that is neither AlarmAck nor notification.
    let mut strange = Vec::new();
    crate::profinet::wire::blocks::emit_block(&mut strange, 0x0110, 0, |o| o.push(0));
    cr.handle_frame(
        t0,
        &from_controller(PDU_DATA, 0x11, 0x0000, SEQ_FIRST, &strange),
    );
    let (header, var) = sent(&cr.poll_frame().expect("an ERR"));
    assert_eq!(
        (header, var),
        (
            (FRAME_ID_LOW, 0x14, 0x01, 0x0000, 0xFFFF),
            vec![0xCF, 0x81, 0xFD, 0x0B]
        )
    );
    assert!(cr.closed());
}

#[test]
fn frames_for_another_endpoint_version_or_peer_are_ignored_and_garbage_never_panics() {
    let mut cr = cr();
    let t0 = Instant::from_millis(0);
    cr.send(t0, alarm(ALARM_DIAGNOSIS));
    cr.poll_frame().expect("the alarm");
    let good = from_controller(PDU_ACK, WINDOW_1, SEQ_NONE, SEQ_FIRST, &[]);
    let mut other_dst = good.clone();
    other_dst[20..22].copy_from_slice(&7u16.to_be_bytes());
    let mut other_src = good.clone();
    other_src[22..24].copy_from_slice(&7u16.to_be_bytes());
    let mut version_2 = good.clone();
    version_2[24] = 0x23;
    let mut with_var_part = from_controller(PDU_ACK, WINDOW_1, SEQ_NONE, SEQ_FIRST, &[0]);
    let mut other_peer = good.clone();
    other_peer[6..12].copy_from_slice(&[2, 0, 0, 0, 0, 9]);
    for frame in [&other_dst, &other_src, &version_2, &with_var_part] {
        assert!(cr.handle_frame(t0, frame));
    }
    assert!(!cr.handle_frame(t0, &other_peer));
    assert_eq!((cr.poll_frame(), cr.poll_event()), (None, None));
    assert!(
        cr.poll_timeout().is_some(),
        "none of them acknowledged the alarm"
    );
    // Cut anywhere before the header's end: never a panic, never an acknowledgement.
    for len in 0..32 {
        assert!(!cr.handle_frame(t0, &good[..len]));
    }
    assert!(cr.poll_timeout().is_some());
    with_var_part[31] = 0xFF;
    assert!(
        !cr.handle_frame(t0, &with_var_part),
        "VarPartLen past the end"
    );
    assert!(cr.handle_frame(t0, &good));
    assert_eq!(cr.poll_timeout(), None);
}

#[test]
fn a_high_priority_alarm_goes_on_0xfc01_with_priority_6_unless_only_low_is_asked() {
    let mut cr = cr();
    let mut process = alarm(0x0002);
    process.high = true;
    cr.send(Instant::from_millis(0), process);
    let frame = cr.poll_frame().expect("the alarm");
    let rta = RtaFrame::parse(&frame).expect("an alarm frame");
    assert_eq!((rta.frame_id, rta.eth.vlan), (FRAME_ID_HIGH, Some(0xC000)));
    assert_eq!(rta.var_part[..2], [0x00, 0x01]);
    // AlarmCRProperties bit 0: low priority only.
    let mut cr = AlarmCr::new(
        &AlarmCrBlockReq {
            properties: 1,
            ..request()
        },
        DEVICE_REF,
        DEVICE,
        CONTROLLER,
    );
    let mut process = alarm(0x0002);
    process.high = true;
    cr.send(Instant::from_millis(0), process);
    let frame = cr.poll_frame().expect("the alarm");
    let rta = RtaFrame::parse(&frame).expect("an alarm frame");
    assert_eq!((rta.frame_id, rta.eth.vlan), (FRAME_ID_LOW, Some(0xA000)));
    assert_eq!(rta.var_part[..2], [0x00, 0x02]);
}

#[test]
fn an_alarm_ack_before_the_transport_ack_lets_the_next_alarm_go_after_the_ack() {
    let mut cr = cr();
    let t0 = Instant::from_millis(0);
    cr.send(t0, alarm(ALARM_DIAGNOSIS));
    cr.send(t0, alarm(ALARM_DIAGNOSIS_DISAPPEARS));
    cr.poll_frame().expect("the first alarm");
    // The AlarmAck whose AckSeqNum does not yet acknowledge the DATA.
    let ack = alarm_ack(ALARM_DIAGNOSIS, 0);
    cr.handle_frame(
        t0,
        &from_controller(PDU_DATA, 0x11, SEQ_FIRST, SEQ_NONE, &ack),
    );
    let (header, _) = sent(&cr.poll_frame().expect("its transport ACK"));
    assert_eq!(header.1, 0x13);
    assert!(matches!(cr.poll_event(), Some(AlarmEvent::Acknowledged(_))));
    assert_eq!(
        cr.poll_frame(),
        None,
        "the first DATA is not acknowledged yet"
    );
    cr.handle_frame(
        t0,
        &from_controller(PDU_ACK, WINDOW_1, SEQ_FIRST, SEQ_FIRST, &[]),
    );
    let (header, var) = sent(&cr.poll_frame().expect("the second alarm"));
    assert_eq!(header, (FRAME_ID_LOW, 0x11, 0x11, 0x0000, 0xFFFF));
    assert_eq!(
        AlarmNotification::parse(&var).map(|a| a.source.alarm_type),
        Some(ALARM_DIAGNOSIS_DISAPPEARS)
    );
}

#[test]
fn every_byte_of_a_controller_frame_changed_is_taken_without_a_panic() {
    let ack = alarm_ack(ALARM_DIAGNOSIS, 0);
    let data = from_controller(PDU_DATA, 0x11, SEQ_FIRST, SEQ_FIRST, &ack);
    for at in 0..data.len() {
        for value in [0x00, 0x01, 0x04, 0x7F, 0x80, 0xFF] {
            let mut cr = cr();
            cr.send(Instant::from_millis(0), alarm(ALARM_DIAGNOSIS));
            cr.poll_frame().expect("the alarm");
            let mut frame = data.clone();
            frame[at] = value;
            cr.handle_frame(Instant::from_millis(1), &frame);
            cr.handle_timeout(Instant::from_millis(1000));
            while let Some(out) = cr.poll_frame() {
                let rta = RtaFrame::parse(&out).expect("the device's frames parse");
                assert_eq!(
                    (rta.header.dst, rta.header.src),
                    (CONTROLLER_REF, DEVICE_REF)
                );
            }
        }
    }
}
