//! Several devices that share one connection to a bus, as one [`BusDevice`]: what one member
//! sends, the others hear at once (as on the wire, the sender does not hear itself) and the bus
//! gets next; what the bus brings, every member hears. One driver thread and one connection
//! serve them all, so a hundred simulated nodes cost the bus's clients one connection instead of
//! a hundred, and the hub one delivery per frame instead of a hundred.

use edsgen_runtime::frame::CanFrame;
use edsgen_runtime::time::Instant;

use crate::vbus::BusDevice;

/// Devices behind one connection (see the module comment).
#[derive(Debug)]
pub struct Segment<D> {
    members: Vec<D>,
    /// The member whose frames are offered first next time, so that none starves the others.
    next: usize,
}

impl<D: BusDevice> Segment<D> {
    /// A segment of `members`.
    pub fn new(members: Vec<D>) -> Self {
        Segment { members, next: 0 }
    }

    /// The members, in the order given.
    pub fn members(&self) -> &[D] {
        &self.members
    }

    /// The members, to change them (a fault raised, say).
    pub fn members_mut(&mut self) -> &mut [D] {
        &mut self.members
    }
}

impl<D: BusDevice> BusDevice for Segment<D> {
    fn handle_frame(&mut self, now: Instant, frame: &CanFrame) {
        for member in &mut self.members {
            member.handle_frame(now, frame);
        }
    }

    fn poll_transmit(&mut self, now: Instant) -> Option<CanFrame> {
        let count = self.members.len();
        for offset in 0..count {
            let sender = (self.next + offset) % count;
            let Some(frame) = self.members[sender].poll_transmit(now) else {
                continue;
            };
            self.next = (sender + 1) % count;
            for (i, member) in self.members.iter_mut().enumerate() {
                if i != sender {
                    member.handle_frame(now, &frame);
                }
            }
            return Some(frame);
        }
        None
    }

    fn poll_timeout(&self) -> Option<Instant> {
        self.members
            .iter()
            .filter_map(BusDevice::poll_timeout)
            .min()
    }

    fn handle_timeout(&mut self, now: Instant) {
        for member in &mut self.members {
            if member.poll_timeout().is_some_and(|at| at <= now) {
                member.handle_timeout(now);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vbus::ScriptedPeer;

    /// A device that answers every frame with id 0x100 + its own number, once.
    #[derive(Debug, Default)]
    struct Echo {
        id: u16,
        heard: Vec<u16>,
        answer: Option<CanFrame>,
        due: Option<Instant>,
    }

    impl BusDevice for Echo {
        fn handle_frame(&mut self, _now: Instant, frame: &CanFrame) {
            let id = frame.std_id().unwrap_or(0);
            self.heard.push(id);
            if id < 0x100 {
                self.answer = CanFrame::new(0x100 + self.id, &[]);
            }
        }
        fn poll_transmit(&mut self, _now: Instant) -> Option<CanFrame> {
            self.answer.take()
        }
        fn poll_timeout(&self) -> Option<Instant> {
            self.due
        }
        fn handle_timeout(&mut self, _now: Instant) {
            self.due = None;
            self.answer = CanFrame::new(0x00F, &[]);
        }
    }

    fn echo(id: u16) -> Echo {
        Echo {
            id,
            ..Echo::default()
        }
    }

    #[test]
    fn a_frame_from_the_bus_reaches_every_member_and_their_answers_reach_each_other() {
        let now = Instant::from_micros(0);
        let mut segment = Segment::new(vec![echo(1), echo(2), echo(3)]);
        segment.handle_frame(now, &CanFrame::new(0x000, &[1, 0]).unwrap());
        let sent: Vec<u16> = std::iter::from_fn(|| segment.poll_transmit(now))
            .map(|f| f.std_id().unwrap())
            .collect();
        assert_eq!(sent, [0x101, 0x102, 0x103]);
        let heard: Vec<Vec<u16>> = segment.members().iter().map(|m| m.heard.clone()).collect();
        assert_eq!(
            heard,
            [
                vec![0x000, 0x102, 0x103],
                vec![0x000, 0x101, 0x103],
                vec![0x000, 0x101, 0x102],
            ]
        );
    }

    #[test]
    fn timers_run_per_member_and_the_next_deadline_is_the_earliest() {
        let mut segment = Segment::new(vec![echo(1), echo(2)]);
        segment.members_mut()[0].due = Some(Instant::from_micros(500));
        segment.members_mut()[1].due = Some(Instant::from_micros(200));
        assert_eq!(segment.poll_timeout(), Some(Instant::from_micros(200)));
        segment.handle_timeout(Instant::from_micros(300));
        assert_eq!(segment.members()[1].due, None);
        assert_eq!(segment.members()[0].due, Some(Instant::from_micros(500)));
        // Member 2's timer frame (0x00F, below 0x100) makes member 1 answer, locally.
        let now = Instant::from_micros(300);
        let sent: Vec<u16> = std::iter::from_fn(|| segment.poll_transmit(now))
            .map(|f| f.std_id().unwrap())
            .collect();
        assert_eq!(sent, [0x00F, 0x101]);
        assert_eq!(segment.members()[0].heard, [0x00F]);
        assert_eq!(segment.members()[1].heard, [0x101]);
    }

    #[test]
    fn no_member_starves_the_others() {
        let now = Instant::from_micros(0);
        let mut peers = vec![ScriptedPeer::new(), ScriptedPeer::new()];
        for n in 0..3u8 {
            peers[0].send_at(now, CanFrame::new(0x181, &[n]).unwrap());
            peers[1].send_at(now, CanFrame::new(0x182, &[n]).unwrap());
        }
        let mut segment = Segment::new(peers);
        segment.handle_timeout(now);
        let order: Vec<(u16, u8)> = std::iter::from_fn(|| segment.poll_transmit(now))
            .map(|f| (f.std_id().unwrap(), f.data()[0]))
            .collect();
        assert_eq!(
            order,
            [
                (0x181, 0),
                (0x182, 0),
                (0x181, 1),
                (0x182, 1),
                (0x181, 2),
                (0x182, 2)
            ]
        );
    }
}
