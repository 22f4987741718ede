//! `edsgen demo --ethercat`: the EC-TX508's steps ([`super::ethercat::workflow`]) over a real
//! wire. As root and with the `ethercrab` feature, a private network namespace gets one end of a
//! veth pair and `edsgen simulate --ethercat END --card ec-tx508 --faults-on-stdin` (this same
//! binary) on it; ethercrab drives it from the other end, in this process's namespace: discovery
//! by identity and SII name, a typed CoE SDO write and read in Pre-Op, Op, then the cyclic
//! steps in EtherCAT frames every 1 ms, the drive fault raised and cleared through the
//! simulator's standard input. Namespace, pair and simulator go when the section ends (or on
//! Ctrl-C, [`crate::netns`]). Otherwise it says why on standard error and runs in this process.

use super::Trace;

/// Runs the EC-TX508's section over a veth pair where it can, else in this process.
pub(super) fn run(trace: &mut Trace) {
    let why_not = if !cfg!(feature = "ethercrab") {
        Some(
            "demo --ethercat needs edsgen built with the `ethercrab` feature (cargo build \
             --features ethercrab)"
                .to_owned(),
        )
    } else if !crate::netns::is_root() {
        Some(crate::netns::not_root("demo --ethercat"))
    } else {
        None
    };
    match why_not {
        Some(why) => {
            eprintln!("{why}; the EC-TX508 runs in this process instead");
            super::ethercat::run(trace);
        }
        #[cfg(feature = "ethercrab")]
        None => wire::run(trace),
        #[cfg(not(feature = "ethercrab"))]
        None => {}
    }
}

#[cfg(feature = "ethercrab")]
pub(super) use wire::{drive as drive_machine, Faults};

#[cfg(feature = "ethercrab")]
mod wire {
    use std::io::Write;
    use std::process::{ChildStdin, Stdio};
    use std::time::{Duration, Instant};

    use edsgen_runtime::ethercat::ethercrab::SdoExt;
    use ethercrab::subdevice_group::Op;
    use ethercrab::{MainDevice, SubDeviceGroup};

    use super::super::ethercat::{workflow, Exchange};
    use super::super::two_namespaces::{Outcome, Server};
    use super::super::{expect, Trace};
    use crate::netns::{End, Network};
    use edsgen_sim::cards::ec_tx508::ethercat::{Inputs, Outputs, IDENTITY};
    use edsgen_sim::cards::ec_tx508::od;

    /// The EC-TX508 on the far end of the pair, in Op, cycled by ethercrab.
    struct Wire {
        runtime: tokio::runtime::Runtime,
        maindevice: MainDevice<'static>,
        group: SubDeviceGroup<64, 4096, ethercrab::DefaultLock, Op>,
        /// Where the drive's fault is raised and cleared.
        faults: Faults,
        first: [u8; Inputs::SIZE],
        /// When the first cycle ran.
        start: Option<Instant>,
        /// When the next cycle is due.
        next: Instant,
    }

    impl Exchange for Wire {
        fn first_inputs(&self) -> [u8; Inputs::SIZE] {
            self.first
        }

        fn now_ms(&self) -> u64 {
            self.start
                .map_or(0, |start| start.elapsed().as_millis() as u64)
        }

        fn exchange(
            &mut self,
            outputs: &[u8; Outputs::SIZE],
        ) -> Result<([u8; Inputs::SIZE], u64), String> {
            let card = self
                .group
                .subdevice(&self.maindevice, 0)
                .map_err(|e| format!("the SubDevice: {e}"))?;
            card.outputs_raw_mut()
                .get_mut(..Outputs::SIZE)
                .ok_or("the outputs image is short")?
                .copy_from_slice(outputs);
            let start = *self.start.get_or_insert_with(Instant::now);
            let (group, maindevice, next) = (&self.group, &self.maindevice, self.next);
            let (sent, received, response) = self
                .runtime
                .block_on(async {
                    tokio::time::sleep_until(next.into()).await;
                    let sent = Instant::now();
                    let response = group.tx_rx(maindevice).await?;
                    Ok::<_, ethercrab::error::Error>((sent, Instant::now(), response))
                })
                .map_err(|e| format!("a cycle: {e}"))?;
            // Outputs the SubDevice no longer takes (its watchdog tripped, say) end the run.
            if !response.all_op() {
                return Err(format!(
                    "the SubDevice left Op: {:?}, working counter {}",
                    response.subdevice_states, response.working_counter
                ));
            }
            let at = (sent - start) + (received - sent) / 2;
            // One cycle per ms; after a late one, the next 1 ms from now.
            self.next = (self.next + Duration::from_millis(1))
                .max(Instant::now() + Duration::from_micros(500));
            let inputs = card.inputs_raw();
            let inputs = inputs
                .get(..Inputs::SIZE)
                .and_then(|i| i.try_into().ok())
                .ok_or("the inputs image is short")?;
            Ok((inputs, at.as_millis() as u64))
        }

        fn raise_fault(&mut self) -> Result<(), String> {
            self.faults.send("fault")
        }

        fn clear_fault(&mut self) -> Result<(), String> {
            self.faults.send("clear")
        }

        fn wire(&self) -> bool {
            true
        }
    }

    /// A simulator's standard input that takes `fault` and `clear`: `edsgen simulate
    /// --faults-on-stdin`'s bare words, or a machine's `fault NAME` and `clear NAME`.
    pub(crate) struct Faults {
        stdin: ChildStdin,
        name: Option<String>,
    }

    impl Faults {
        /// A machine's standard input, for the device called `name` in its file.
        pub(crate) fn named(stdin: ChildStdin, name: &str) -> Faults {
            Faults {
                stdin,
                name: Some(name.to_owned()),
            }
        }

        fn send(&mut self, word: &str) -> Result<(), String> {
            match &self.name {
                Some(name) => writeln!(self.stdin, "{word} {name}"),
                None => writeln!(self.stdin, "{word}"),
            }
            .map_err(|e| format!("the simulator's stdin: {e}"))
        }
    }

    pub(super) fn run(trace: &mut Trace) {
        let mut net = match Network::create("ecat", 1) {
            Ok(net) => net,
            Err(problem) => {
                trace.heading("EC-TX508 (EtherCAT over a veth pair)");
                trace.step("a network namespace and a veth pair", Err(problem));
                return;
            }
        };
        let namespace = net.namespace(0).unwrap_or_default().to_owned();
        trace.heading(&format!(
            "EC-TX508 (EtherCAT over a veth pair, the SubDevice in namespace {namespace}): CiA \
             402 cyclic synchronous velocity, 1 ms cycle"
        ));
        let lines = match on_wire(trace, &mut net) {
            Ok(lines) => lines,
            Err((problem, lines)) => {
                trace.step("EC-TX508 over EtherCAT", Err(problem));
                lines
            }
        };
        drop(net);
        for line in lines {
            trace.line(None, format!("simulator: {line}"));
        }
    }

    /// The section on the wire; the simulator's standard error after its "serving" line, once
    /// it is stopped (with the problem, if any).
    fn on_wire(trace: &mut Trace, net: &mut Network) -> Outcome {
        let bare = |problem: String| (problem, Vec::new());
        let (master, device) = net.veth(End::Host, End::Namespace(0)).map_err(bare)?;
        let exe = std::env::current_exe().map_err(|e| bare(format!("this program: {e}")))?;
        let mut command = net.command(0, &exe).map_err(bare)?;
        command
            .args(["simulate", "--ethercat", &device, "--card", "ec-tx508"])
            .arg("--faults-on-stdin")
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::piped());
        let shown = format!(
            "ip netns exec {} edsgen simulate --ethercat {device} --card ec-tx508 \
             --faults-on-stdin; ethercrab on {master}",
            net.namespace(0).unwrap_or_default()
        );
        let ready = ("serving ", false);
        let sim = Server::start(trace, net, &mut command, shown, "the simulator", ready)?;
        let result = net
            .child(sim.id)
            .and_then(|child| child.stdin.take())
            .ok_or_else(|| "the simulator's standard input".to_owned())
            .and_then(|stdin| drive(trace, &master, Faults { stdin, name: None }));
        // SIGTERM: the simulator says what it served, and exits.
        sim.stop(net, Duration::from_secs(5), result)
    }

    /// Discovery, a typed SDO write and read in Pre-Op, Op, then the cyclic steps.
    pub(crate) fn drive(trace: &mut Trace, iface: &str, faults: Faults) -> Result<(), String> {
        let runtime = crate::ecat::runtime()?;
        let (maindevice, group) = runtime.block_on(crate::ecat::discover(iface))?;
        let count = group.len();
        let card = group
            .subdevice(&maindevice, 0)
            .map_err(|e| format!("{count} SubDevice(s): {e}"))?;
        let id = card.identity();
        let seen = format!(
            "{count} SubDevice, vendor {:#x}, product {:#x}, revision {}, \"{}\"",
            id.vendor_id,
            id.product_id,
            id.revision,
            card.name()
        );
        let found = count == 1 && IDENTITY.matches_subdevice(&card) && card.name() == "EC-TX508";
        trace.step(
            "discovery: the EC-TX508 by its identity and its SII name",
            if found { Ok(seen) } else { Err(seen) },
        );
        let mode = runtime.block_on(async {
            card.write_entry(od::OPERATION_MODE, 9).await?;
            card.read_entry(od::OPERATION_MODE).await
        });
        trace.step(
            "6060h = 9 by CoE SDO in Pre-Op, read back (typed od::OPERATION_MODE)",
            mode.map_err(|e| format!("{e}"))
                .and_then(|mode| expect(mode, 9)),
        );
        let group = runtime
            .block_on(group.into_op(&maindevice))
            .map_err(|e| format!("to Op: {e}"))?;
        let card = group
            .subdevice(&maindevice, 0)
            .map_err(|e| format!("the SubDevice in Op: {e}"))?;
        let sizes = (card.outputs_raw().len(), card.inputs_raw().len());
        // One cycle, so that the master's first look at the inputs sees the drive.
        runtime
            .block_on(group.tx_rx(&maindevice))
            .map_err(|e| format!("the first cycle: {e}"))?;
        let mut first = [0; Inputs::SIZE];
        if let Some(inputs) = card.inputs_raw().get(..Inputs::SIZE) {
            first.copy_from_slice(inputs);
        }
        trace.step(
            "Pre-Op → Safe-Op → Op: the 21-byte outputs (1600h), the 23-byte inputs (1A00h)",
            expect(sizes, (Outputs::SIZE, Inputs::SIZE)),
        );
        let mut wire = Wire {
            runtime,
            maindevice,
            group,
            faults,
            first,
            start: None,
            next: Instant::now(),
        };
        workflow(trace, &mut wire)
    }
}
