//! Hostile packets at `edsgen simulate --enip 127.0.0.1:PORT --card goodrive350-enip` (issue
//! 34), then a real client: 3,000 encapsulation messages and datagrams mutated from a good
//! exchange (RegisterSession, ListIdentity, ListServices, Get_Attribute_Single by SendRRData,
//! a class-1 Forward_Open, SendUnitData, a class-1 datagram, UnRegisterSession; bytes flipped,
//! cut, lengthened, length fields changed, random bytes; a deterministic seed), a third each on
//! TCP (a new connection every 100), on UDP at the encapsulation port and on UDP 2222. The
//! adapter must then still serve cpppo's Get_Attribute_Single and ListIdentity. Without the venv
//! the test is skipped (`process_support`); under `CI=true` it fails.

mod process_support;

use std::io::{Read, Write};
use std::net::{TcpStream, UdpSocket};
use std::process::Command;
use std::time::Duration;

use process_support::{python, Process};

/// An encapsulation message: command, session, data (context and options 0).
fn encap(command: u16, session: u32, data: &[u8]) -> Vec<u8> {
    let mut m = command.to_le_bytes().to_vec();
    m.extend_from_slice(&(data.len() as u16).to_le_bytes());
    m.extend_from_slice(&session.to_le_bytes());
    m.extend_from_slice(&[0; 16]);
    m.extend_from_slice(data);
    m
}

/// SendRRData/SendUnitData's CPF: interface handle, timeout, two items.
fn cpf(first: (u16, &[u8]), second: (u16, &[u8])) -> Vec<u8> {
    let mut d = vec![0, 0, 0, 0, 0, 0, 2, 0];
    for (kind, data) in [first, second] {
        d.extend_from_slice(&kind.to_le_bytes());
        d.extend_from_slice(&(data.len() as u16).to_le_bytes());
        d.extend_from_slice(data);
    }
    d
}

/// A good exchange with the card, session 1 (the adapter's first handle).
fn recorded() -> Vec<Vec<u8>> {
    let get_name = [0x0E, 3, 0x20, 0x01, 0x24, 0x01, 0x30, 0x07];
    // Forward_Open 150 -> 100, 32 bytes each way (+ 6 and + 2), RPI 50 ms.
    let mut open = vec![0x54, 2, 0x20, 0x06, 0x24, 0x01, 0x0A, 0x0E];
    open.extend_from_slice(&[0, 0, 0, 0, 0x64, 0, 0, 0, 9, 0, 0xE5, 0xED, 1, 0, 0, 0]);
    open.extend_from_slice(&[0, 0, 0, 0]);
    open.extend_from_slice(&50_000u32.to_le_bytes());
    open.extend_from_slice(&(0x4800u16 | 38).to_le_bytes());
    open.extend_from_slice(&50_000u32.to_le_bytes());
    open.extend_from_slice(&(0x4800u16 | 34).to_le_bytes());
    open.extend_from_slice(&[0x01, 4, 0x20, 0x04, 0x24, 0x01, 0x2C, 0x96, 0x2C, 0x64]);
    let mut io = vec![0x02, 0, 0x02, 0x80, 0x08, 0, 0x01, 0, 0, 0x10, 1, 0, 0, 0];
    io.extend_from_slice(&[0xB1, 0, 38, 0, 1, 0, 1, 0, 0, 0]);
    io.extend_from_slice(&[0; 32]);
    let unit = cpf(
        (0xA1, &[1, 0, 0, 0x10]),
        (0xB1, &[[1, 0].as_slice(), &get_name].concat()),
    );
    vec![
        encap(0x65, 0, &[1, 0, 0, 0]),
        encap(0x63, 0, &[]),
        encap(0x04, 0, &[]),
        encap(0x6F, 1, &cpf((0, &[]), (0xB2, &get_name))),
        encap(0x6F, 1, &cpf((0, &[]), (0xB2, &open))),
        encap(0x70, 1, &unit),
        io,
        encap(0x66, 1, &[]),
    ]
}

/// xorshift64: the same bytes on every run.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }

    fn byte(&mut self) -> u8 {
        self.next() as u8
    }
}

fn mutate(rng: &mut Rng, good: &[u8]) -> Vec<u8> {
    let mut m = good.to_vec();
    match rng.below(6) {
        0 => {
            let at = rng.below(m.len());
            m[at] ^= 1 << rng.below(8);
        }
        1 => m.truncate(rng.below(m.len())),
        2 => (0..1 + rng.below(40)).for_each(|_| m.push(rng.byte())),
        3 if m.len() >= 4 => {
            m[2] = rng.byte();
            m[3] = rng.byte();
        }
        4 => {
            let at = rng.below(m.len());
            m[at] = rng.byte();
        }
        _ => m = (0..rng.below(80)).map(|_| rng.byte()).collect(),
    }
    m
}

fn drain(stream: &mut TcpStream) {
    let mut buf = [0u8; 4096];
    while matches!(stream.read(&mut buf), Ok(n) if n > 0) {}
}

#[test]
fn the_adapter_survives_hostile_packets_and_cpppo_reads_it_after() {
    let Some(python) = python() else { return };
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .expect("a free port")
        .port();
    let address = format!("127.0.0.1:{port}");
    let adapter = Process::edsgen(&["simulate", "--enip", &address, "--card", "goodrive350-enip"]);
    adapter.stderr_line(|l| l.starts_with("serving"), Duration::from_secs(10));
    let good = recorded();
    let mut rng = Rng(34);
    let udp = UdpSocket::bind("127.0.0.1:0").expect("a UDP socket");
    let connect = || {
        let s = TcpStream::connect(&address).expect("the adapter accepts");
        s.set_read_timeout(Some(Duration::from_millis(2))).unwrap();
        s
    };
    let mut tcp = connect();
    for n in 0..3000 {
        let pick = rng.below(good.len());
        let message = mutate(&mut rng, &good[pick]);
        match n % 3 {
            0 => {
                if n % 100 == 0 {
                    tcp = connect();
                    let _ = tcp.write_all(&good[0]);
                }
                let _ = tcp.write_all(&message);
                drain(&mut tcp);
            }
            1 => {
                let _ = udp.send_to(&message, &address);
            }
            _ => {
                let _ = udp.send_to(&message, "127.0.0.1:2222");
            }
        }
    }
    drop(tcp);
    // cpppo reads the Identity object's product name and the card's input assembly.
    let out = Command::new(&python)
        .args([
            "-m",
            "cpppo.server.enip.get_attribute",
            "-S",
            "-a",
            &address,
        ])
        .args(["@1/1/7", "@1/1/3"])
        .current_dir(process_support::root())
        .output()
        .expect("cpppo runs");
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    let values: Vec<&str> = text
        .lines()
        .filter_map(|l| l.split_once(" == ").map(|(_, v)| v.trim()))
        .collect();
    let mut name = vec![28u8];
    name.extend_from_slice(b"Goodrive350 EtherNet/IP card");
    assert_eq!(
        values,
        [format!("{name:?}"), "[94, 1]".to_owned()],
        "{text}{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
