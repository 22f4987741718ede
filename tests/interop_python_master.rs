//! The edsgen master against python `canopen` 2.4.1 LocalNodes in another process, through the
//! socketcand hub on 127.0.0.1 (`scripts/interop_device.py`): boot-up, typed SDO both ways,
//! segmented upload of a string, a block upload python answers normally, a block download and a
//! read of a missing object it aborts, NMT, heartbeat loss and recovery, and EMCY.
//!
//! Without python the test is skipped with a message, except under `CI=true`. Every wait is
//! bounded and the python process is killed when the test ends.

mod process_support;

use std::path::Path;
use std::time::Duration;

use edsgen_runtime::master::blocking::{Master, MasterError, MasterEvent};
use edsgen_runtime::master::{Emergency, Mode, MonitorEvent, SdoError, Watch};
use edsgen_runtime::transport::hub::{Hub, HubOptions};
use edsgen_runtime::transport::socketcand::SocketcandClient;
use edsgen_runtime::wire::heartbeat::NmtState;
use edsgen_runtime::wire::nmt::NmtCommand;
use edsgen_runtime::wire::sdo::Multiplexer;
use edsgen_runtime::Entry;
use process_support::{python, root, Process};

const WAIT: Duration = Duration::from_secs(10);

/// `scripts/interop_device.py`: a python LocalNode, once it says `READY`.
struct Device(Process);

impl Device {
    fn start(python: &Path, port: u16, eds: &str, node_id: u8) -> Device {
        let args = [port.to_string(), eds.to_owned(), node_id.to_string()];
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let device = Process::python(python, "scripts/interop_device.py", &args);
        device.stdout_line(|l| l == "READY", WAIT);
        Device(device)
    }

    /// Sends `command` and waits for its `DONE <verb>` line; what follows the verb.
    fn command(&mut self, command: &str) -> String {
        self.0.send_line(command);
        let verb = command.split_whitespace().next().unwrap();
        let done = format!("DONE {verb}");
        let line = self.0.stdout_line(|l| l.starts_with(&done), WAIT);
        line[done.len()..].trim_start().to_owned()
    }
}

fn monitor_events(master: &mut Master<SocketcandClient>) -> Vec<MonitorEvent> {
    std::iter::from_fn(|| master.poll_event())
        .filter_map(|e| match e {
            MasterEvent::Monitor(m) => Some(m),
            _ => None,
        })
        .collect()
}

#[test]
fn the_edsgen_master_drives_a_python_local_node() {
    let Some(python) = python() else { return };
    let hub = Hub::start("127.0.0.1:0", HubOptions::default()).unwrap();
    let transport = SocketcandClient::connect(hub.local_addr(), "can0", WAIT).unwrap();
    let mut master = Master::new(transport);
    let eds = root().join("eds/goodrive350.eds").display().to_string();
    let mut device = Device::start(&python, hub.local_addr().port(), &eds, 6);
    master.wait_for_boot(6, WAIT).unwrap();

    // Expedited, typed, both ways.
    assert_eq!(master.read(6, Entry::<u32>::new(0x1000, 0)).unwrap(), 0);
    master.write(6, Entry::<u16>::new(0x1017, 0), 0).unwrap();
    master
        .write(6, Entry::<u32>::new(0x1006, 0), 0x0001_0000)
        .unwrap();
    assert_eq!(
        master.read(6, Entry::<u32>::new(0x1006, 0)).unwrap(),
        0x0001_0000
    );
    // Segmented upload; a block upload python answers as a normal one (CiA 301 allows it).
    let name = Multiplexer::new(0x1008, 0);
    assert_eq!(
        master.upload(6, name, Mode::Normal).unwrap(),
        b"INVT CANopen"
    );
    assert_eq!(
        master.upload(6, name, Mode::Block).unwrap(),
        b"INVT CANopen"
    );
    // Aborts from python: no block download, no object 5FFFh.
    let block = master.download(6, Multiplexer::new(0x1006, 0), &[0; 4], Mode::Block);
    assert!(matches!(
        block,
        Err(MasterError::Sdo {
            error: SdoError::Server(0x0504_0001),
            ..
        })
    ));
    let missing = master.upload(6, Multiplexer::new(0x5FFF, 0), Mode::Normal);
    assert!(matches!(
        missing,
        Err(MasterError::Sdo {
            error: SdoError::Server(0x0602_0000),
            ..
        })
    ));

    // NMT and heartbeat: the state change, the loss and the recovery.
    master.poll_event();
    device.command("heartbeat 50");
    master
        .watch(
            6,
            Watch::Heartbeat(edsgen_runtime::Duration::from_millis(200)),
        )
        .unwrap();
    master.listen(Duration::from_millis(150)).unwrap();
    master.nmt(NmtCommand::Start, 6).unwrap();
    master.listen(Duration::from_millis(150)).unwrap();
    device.command("heartbeat 0");
    master.listen(Duration::from_millis(400)).unwrap();
    device.command("heartbeat 50");
    master.listen(Duration::from_millis(150)).unwrap();
    assert_eq!(
        monitor_events(&mut master),
        [
            MonitorEvent::StateChanged {
                node_id: 6,
                from: None,
                to: NmtState::PreOperational
            },
            MonitorEvent::StateChanged {
                node_id: 6,
                from: Some(NmtState::PreOperational),
                to: NmtState::Operational
            },
            MonitorEvent::Lost { node_id: 6 },
            MonitorEvent::Recovered {
                node_id: 6,
                state: NmtState::Operational
            },
        ]
    );

    // EMCY.
    device.command("emcy");
    master.listen(Duration::from_millis(100)).unwrap();
    let emergencies: Vec<Emergency> = std::iter::from_fn(|| master.poll_event())
        .filter_map(|e| match e {
            MasterEvent::Emergency(e) => Some(e),
            _ => None,
        })
        .collect();
    assert_eq!(
        emergencies,
        [Emergency {
            node_id: 6,
            code: 0x2310,
            register: 0x03,
            manufacturer: [1, 2, 3, 4, 5]
        }]
    );
    device.command("quit");
    hub.stop();
}
