//! The FPGA side of the serial FPGA link ([`protocol::fpga_link`]): an FPGA answering a
//! controller that talks to it over a byte stream (a QEMU board's second UART).
//!
//! The FPGA is any [`FpgaBus`]: the golden model ([`SimBus`](crate::in_process::SimBus))
//! or the Verilated FITkit block behind the SPI driver ([`RtlBus`](crate::rtl::RtlBus)).
//! Each request is the bus call of the same name, so a QEMU board reaches the RTL through
//! exactly the driver a FITkit MCU runs, only one serial hop further away.
//!
//! Sans-I/O like [`protocol::link`]: bytes in through [`FpgaServer::input`], bytes out
//! through [`FpgaServer::poll_transmit`], time passed in by the caller, so `fpgfx-sim` owns
//! the port and tests can drive it from memory.

use heapless::Vec;
use protocol::bus::LayoutId;
use protocol::fpga_link::{
    Fault, FaultCode, FpgaReply, FpgaRequest, FpgaStatus, Identity, FPGA_SCHEMA_HASH,
};
use protocol::frame::{decode, encode, READ_CHUNK};
use protocol::link::{Event, Link};
use protocol::MAX_PAYLOAD;

use protocol::bus::{BusLayout, MAX_RECORDS};
use protocol::frame::Caps;

use firmware::{FitkitSpiError, FpgaBus, MmioError};
use sim_target::DeviceError;

/// An FPGA bus error as the link reports it: the controller receives only a
/// [`FaultCode`], the operator's log the text.
pub trait Served: core::fmt::Display {
    /// The code the controller is told.
    fn fault_code(&self) -> FaultCode;
}

impl Served for DeviceError {
    fn fault_code(&self) -> FaultCode {
        match self {
            DeviceError::Packet { .. } | DeviceError::Raster { .. } => FaultCode::Packet,
            DeviceError::Overrun { .. } => FaultCode::Overrun,
            DeviceError::Setup(_) | DeviceError::NoSetup(_) => FaultCode::Setup,
            DeviceError::Registers { .. } => FaultCode::OutOfRange,
            DeviceError::Scene(_) | DeviceError::Render(_) => FaultCode::Scene,
            // A variant added later is still a refusal of what was sent.
            _ => FaultCode::Packet,
        }
    }
}

impl<E: core::fmt::Debug> Served for FitkitSpiError<E> {
    fn fault_code(&self) -> FaultCode {
        match self {
            FitkitSpiError::Block(_) | FitkitSpiError::Unsupported(_) => FaultCode::Packet,
            FitkitSpiError::NoSetup => FaultCode::Setup,
            FitkitSpiError::Timeout { .. } => FaultCode::Stuck,
            FitkitSpiError::Spi(_) | FitkitSpiError::Frame(_) => FaultCode::Bus,
            // A variant added later is still a refusal of what was sent.
            _ => FaultCode::Packet,
        }
    }
}

impl<E: core::fmt::Debug + core::fmt::Display> Served for MmioError<E> {
    fn fault_code(&self) -> FaultCode {
        match self {
            MmioError::Stuck { .. } => FaultCode::Stuck,
            MmioError::Access(_) | MmioError::Identity { .. } => FaultCode::Bus,
            MmioError::OutOfMap { .. } => FaultCode::OutOfRange,
            // A variant added later is still a refusal of what was sent.
            _ => FaultCode::Packet,
        }
    }
}

/// An FPGA behind a link.
pub struct FpgaServer<B> {
    link: Link<8>,
    bus: B,
    /// What [`FpgaRequest::Identify`] answers: the bus cannot say, its owner knows.
    caps: Caps,
    layout: &'static BusLayout,
    /// Requests since the last reset, for [`Fault::request`].
    requests: u32,
    /// The first refused posted request since the last answer.
    fault: Option<Fault>,
    /// The first error's full text, for the operator's log.
    fault_text: Option<String>,
    /// A packet whose last part has not arrived.
    partial: Option<(u8, Vec<u64, MAX_RECORDS>)>,
    /// Answers not yet accepted by the link (its window was full).
    outbox: std::collections::VecDeque<std::vec::Vec<u8>>,
}

impl<B: FpgaBus> FpgaServer<B>
where
    B::Error: Served,
{
    /// Serves `bus`, which draws in `layout` and can do what `caps` says.
    pub fn new(bus: B, caps: Caps, layout: &'static BusLayout) -> Self {
        Self {
            link: Link::new(Default::default()),
            bus,
            caps,
            layout,
            requests: 0,
            fault: None,
            fault_text: None,
            partial: None,
            outbox: Default::default(),
        }
    }

    /// The FPGA behind the link, for a caller that inspects it directly.
    pub fn bus(&mut self) -> &mut B {
        &mut self.bus
    }

    /// The text of the last refused request since it was reported, taken once (the
    /// controller receives only a [`FaultCode`]; the operator wants the whole story).
    pub fn take_fault_text(&mut self) -> Option<String> {
        self.fault_text.take()
    }

    /// The FPGA link's own counters (frames sent, resent, dropped for CRC), so a noisy
    /// second UART shows in the stats apart from the host link's.
    pub fn link_counters(&self) -> protocol::frame::LinkCounters {
        self.link.counters()
    }

    /// Handles received bytes: every complete request is executed at once (a ray-traced
    /// frame renders inside this call).
    pub fn input(&mut self, now_ms: u64, mut bytes: &[u8]) {
        loop {
            let (used, event) = self.link.handle_input(now_ms, bytes);
            bytes = &bytes[used..];
            match event {
                Some(Event::Data(payload)) => {
                    // Requests borrow texel bytes from the link's buffer: copy the payload
                    // so the device can be driven while the link is borrowed again.
                    let payload: std::vec::Vec<u8> = payload.to_vec();
                    self.request(&payload);
                }
                Some(Event::PeerReset { .. }) => {
                    // A controller that restarts expects a powered-on FPGA.
                    self.power_on();
                }
                Some(Event::Synced) => {}
                None if bytes.is_empty() => break,
                None => {}
            }
        }
    }

    fn power_on(&mut self) {
        if let Err(e) = self.bus.reset() {
            self.refuse(0, &e);
        }
        self.requests = 0;
        self.fault = None;
        self.partial = None;
        self.outbox.clear();
    }

    /// Runs the FPGA for a while (executes queued FIFO packets); call it whenever the
    /// line is quiet. Returns whether there was work.
    pub fn work(&mut self) -> bool {
        let last = self.requests.saturating_sub(1);
        // An FPGA without a raster block (the ray-casting core) has no FIFO to run, and
        // no registers to ask about one.
        if !self.caps.raster {
            return false;
        }
        match self.bus.idle() {
            Ok(true) => false,
            Ok(false) => {
                if let Err(e) = self.bus.wait() {
                    self.refuse(last, &e);
                }
                true
            }
            Err(e) => {
                self.refuse(last, &e);
                false
            }
        }
    }

    /// Runs the link's timers and writes the next frame to send into `out`
    /// ([`protocol::link::MAX_FRAME`] bytes), if any.
    pub fn poll_transmit(&mut self, now_ms: u64, out: &mut [u8]) -> Option<usize> {
        while let Some(front) = self.outbox.front() {
            if self.link.send(now_ms, front).is_err() {
                break;
            }
            self.outbox.pop_front();
        }
        self.link.handle_timeout(now_ms);
        self.link.poll_transmit(now_ms, out)
    }

    fn refuse(&mut self, request: u32, e: &B::Error) {
        self.fault_code(request, e.fault_code(), e.to_string());
    }

    fn fault_code(&mut self, request: u32, code: FaultCode, text: String) {
        if self.fault.is_none() {
            self.fault = Some(Fault { request, code });
            self.fault_text = Some(format!("request #{request}: {text}"));
        }
    }

    fn answer(&mut self, reply: FpgaReply) {
        // A fault reported since the last answer replaces this answer, once.
        let reply = match self.fault.take() {
            Some(f) => FpgaReply::Fault(f),
            None => reply,
        };
        let mut buf = [0u8; MAX_PAYLOAD];
        // Every reply is bounded below MAX_PAYLOAD (a protocol test checks the worst case).
        if let Ok(bytes) = encode(&reply, &mut buf) {
            self.outbox.push_back(bytes.to_vec());
        }
    }

    fn request(&mut self, payload: &[u8]) {
        let index = self.requests;
        self.requests = self.requests.wrapping_add(1);
        let req = match decode::<FpgaRequest<'_>>(payload) {
            Ok(r) => r,
            Err(e) => {
                self.fault_code(index, FaultCode::Malformed, format!("undecodable: {e}"));
                return;
            }
        };
        // An answered request whose bus call fails is answered with the fault, so the
        // controller never waits for an answer that will not come.
        let answered = matches!(
            req,
            FpgaRequest::Identify
                | FpgaRequest::Status
                | FpgaRequest::ReadLen(_)
                | FpgaRequest::Read { .. }
                | FpgaRequest::Counters
        );
        let result: Result<Option<FpgaReply>, B::Error> = match req {
            FpgaRequest::Identify => match LayoutId::of(self.layout) {
                Some(layout) => Ok(Some(FpgaReply::Identity(Identity {
                    schema_hash: FPGA_SCHEMA_HASH,
                    caps: self.caps,
                    layout,
                }))),
                None => {
                    let text = format!("layout {} has no wire id", self.layout.name);
                    self.fault_code(index, FaultCode::Setup, text);
                    self.answer_fault();
                    Ok(None)
                }
            },
            FpgaRequest::Reset => {
                self.power_on();
                // The reset request itself is #0 of the new count.
                self.requests = 1;
                Ok(None)
            }
            FpgaRequest::Status => self.status().map(|s| Some(FpgaReply::Status(s))),
            FpgaRequest::Push {
                channel,
                last,
                records,
            } => self.push(index, channel, last, &records).map(|()| None),
            FpgaRequest::RasterSetup(s) => self.bus.raster_setup(&s).map(|()| None),
            FpgaRequest::Regs { offset, words } => {
                self.bus.write_regs(offset, &words).map(|()| None)
            }
            FpgaRequest::Texels { offset, bytes } => {
                self.bus.write_texels(offset, bytes).map(|()| None)
            }
            FpgaRequest::Start(s) => self.bus.start(&s).map(|()| None),
            FpgaRequest::Stop => self.bus.stop().map(|()| None),
            FpgaRequest::ReadLen(r) => self.bus.read_len(&r).map(|n| Some(FpgaReply::ReadLen(n))),
            FpgaRequest::Read { req, offset, len } => {
                let len = usize::from(len);
                match self.bus.read_len(&req) {
                    Ok(total)
                        if len <= READ_CHUNK
                            && total.is_some_and(|t| {
                                u64::from(offset) + len as u64 <= u64::from(t)
                            }) =>
                    {
                        let mut data: Vec<u8, READ_CHUNK> = Vec::new();
                        // len ≤ READ_CHUNK was checked above.
                        let _ = data.resize(len, 0);
                        self.bus
                            .read(&req, offset, &mut data)
                            .map(|()| Some(FpgaReply::Data(data)))
                    }
                    Ok(total) => {
                        self.fault_code(
                            index,
                            FaultCode::OutOfRange,
                            format!(
                                "read of {len} bytes at {offset} outside the buffer ({total:?})"
                            ),
                        );
                        self.answer_fault();
                        Ok(None)
                    }
                    Err(e) => Err(e),
                }
            }
            FpgaRequest::Counters => self.bus.counters().map(|c| Some(FpgaReply::Counters(c))),
        };
        match result {
            Ok(Some(reply)) => self.answer(reply),
            Ok(None) => {}
            Err(e) => {
                self.refuse(index, &e);
                if answered {
                    self.answer_fault();
                }
            }
        }
    }

    fn status(&mut self) -> Result<FpgaStatus, B::Error> {
        let done = self.bus.poll_done()?;
        let (fifo_free, idle) = match self.caps.raster {
            true => (
                self.bus.fifo_free()?.min(usize::from(u16::MAX)) as u16,
                self.bus.idle()?,
            ),
            false => (0, true),
        };
        Ok(FpgaStatus {
            fifo_free,
            idle,
            done,
        })
    }

    /// Answers with the fault just recorded (in place of the reply that failed).
    fn answer_fault(&mut self) {
        if let Some(f) = self.fault.take() {
            self.answer(FpgaReply::Fault(f));
        }
    }

    fn push(
        &mut self,
        index: u32,
        channel: u8,
        last: bool,
        records: &[u64],
    ) -> Result<(), B::Error> {
        let (ch, buf) = self.partial.get_or_insert_with(|| (channel, Vec::new()));
        if *ch != channel || buf.extend_from_slice(records).is_err() {
            self.partial = None;
            self.fault_code(
                index,
                FaultCode::Malformed,
                format!(
                    "packet part on channel {channel:#04x} does not continue the open packet \
                     or exceeds {MAX_RECORDS} records"
                ),
            );
            return Ok(());
        }
        if !last {
            return Ok(());
        }
        let Some((ch, buf)) = self.partial.take() else {
            return Ok(());
        };
        self.bus.push_packet(ch, &buf)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The controller decides whether to reset the FPGA from the code alone, so a stuck
    /// block and a broken bus must not read as a refused packet.
    #[test]
    fn fitkit_errors_keep_their_kind_over_the_link() {
        type E = FitkitSpiError<()>;
        let stuck = E::Timeout {
            waiting_for: "busy low",
            polls: 3,
        };
        assert_eq!(stuck.fault_code(), FaultCode::Stuck);
        assert_eq!(E::Spi(()).fault_code(), FaultCode::Bus);
        assert_eq!(E::NoSetup.fault_code(), FaultCode::Setup);
        assert_eq!(
            E::Unsupported("circle unit").fault_code(),
            FaultCode::Packet
        );
    }
}
