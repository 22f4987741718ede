//! A PROFIBUS-DP line for profirust's master: its PHY over a serial line opened as a file (a
//! pseudo-terminal, or an RS-485 adapter set up beforehand with `stty`): profirust's own serial
//! PHYs query the line with ioctls a pseudo-terminal refuses. A reader thread hands the received
//! bytes over; writes go out at once, and the transmission counts as going on for the telegram's
//! time on the wire (11 bits a byte at the bus's rate), so that profirust's timing holds.

use std::fs::File;
use std::io::{Read, Write};
use std::sync::mpsc::{self, Receiver};

use edsgen_runtime::dp::fdl::{self, FdlError, Repr};
use profirust::phy::ProfibusPhy;
use profirust::time::Instant;
use profirust::Baudrate;

/// The PHY.
pub struct TtyPhy {
    writer: File,
    rx: Receiver<Vec<u8>>,
    received: Vec<u8>,
    baud: Baudrate,
    sending_until: Option<Instant>,
}

impl TtyPhy {
    /// The PHY on an open line at `baud`.
    pub fn new(port: File, baud: Baudrate) -> std::io::Result<Self> {
        let mut reader = port.try_clone()?;
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || {
            let mut buf = [0u8; 512];
            while let Ok(n) = reader.read(&mut buf) {
                if n == 0 || tx.send(buf[..n].to_vec()).is_err() {
                    return;
                }
            }
        });
        Ok(TtyPhy {
            writer: port,
            rx,
            received: Vec::new(),
            baud,
            sending_until: None,
        })
    }
}

impl TtyPhy {
    /// Sends `request` and waits up to `timeout` for a telegram from station `from` (to
    /// `to`); bytes that are no such telegram are dropped. For `dp scan`, which asks each
    /// address once without profirust's token cycle.
    pub fn request(
        &mut self,
        request: &[u8],
        from: u8,
        to: u8,
        timeout: std::time::Duration,
    ) -> Option<Vec<u8>> {
        while self.rx.try_recv().is_ok() {}
        self.received.clear();
        self.writer.write_all(request).ok()?;
        let _ = self.writer.flush();
        let deadline = std::time::Instant::now() + timeout;
        loop {
            let left = deadline.checked_duration_since(std::time::Instant::now())?;
            let bytes = self.rx.recv_timeout(left).ok()?;
            self.received.extend(bytes);
            while !self.received.is_empty() {
                match fdl::parse(&self.received) {
                    Ok((Repr::Data(t), used)) => {
                        let answer = t.sa == from && t.da == to && !t.is_request();
                        let telegram: Vec<u8> = self.received.drain(..used).collect();
                        if answer {
                            return Some(telegram);
                        }
                    }
                    Ok((_, used)) => {
                        self.received.drain(..used);
                    }
                    Err(FdlError::Incomplete) => break,
                    Err(_) => {
                        self.received.remove(0);
                    }
                }
            }
        }
    }

    /// Station `address`'s six standard diagnosis bytes (Slave_Diag from `master`, one try of
    /// `timeout`), if it answers.
    pub fn slave_diag(
        &mut self,
        master: u8,
        address: u8,
        timeout: std::time::Duration,
    ) -> Option<[u8; 6]> {
        let diag = request(master, address, fdl::request::SRD_LOW, Some(60));
        let answer = self.request(&diag, address, master, timeout)?;
        match fdl::parse(&answer) {
            Ok((Repr::Data(t), _)) => t.data.get(..6)?.try_into().ok(),
            _ => None,
        }
    }
}

impl ProfibusPhy for TtyPhy {
    fn poll_transmission(&mut self, now: Instant) -> bool {
        match self.sending_until {
            Some(until) if now < until => true,
            _ => {
                self.sending_until = None;
                false
            }
        }
    }

    fn transmit_data<F, R>(&mut self, now: Instant, f: F) -> R
    where
        F: FnOnce(&mut [u8]) -> (usize, R),
    {
        let mut buffer = [0u8; 256];
        let (length, result) = f(&mut buffer);
        if length > 0 && self.writer.write_all(&buffer[..length]).is_ok() {
            let _ = self.writer.flush();
            let bits = u32::try_from(length * 11).unwrap_or(u32::MAX);
            self.sending_until = Some(now + self.baud.bits_to_time(bits));
        }
        result
    }

    fn receive_data<F, R>(&mut self, _now: Instant, f: F) -> R
    where
        F: FnOnce(&[u8]) -> (usize, R),
    {
        while let Ok(bytes) = self.rx.try_recv() {
            self.received.extend(bytes);
        }
        let (drop, result) = f(&self.received);
        self.received.drain(..drop.min(self.received.len()));
        result
    }
}

/// A request from `master` to `address`: SD1 without SAPs, SD2 with them (SSAP 62).
pub fn request(master: u8, address: u8, function: u8, dsap: Option<u8>) -> Vec<u8> {
    let mut buf = [0u8; 16];
    let telegram = edsgen_runtime::dp::fdl::DataRepr {
        da: address,
        sa: master,
        dsap,
        ssap: dsap.map(|_| 62),
        fc: 0x40 | function,
        data: &[],
    };
    // At most 11 bytes.
    let len = telegram.emit(&mut buf).unwrap_or(0);
    buf[..len].to_vec()
}
