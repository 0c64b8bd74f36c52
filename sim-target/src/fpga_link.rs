//! The FPGA side of the serial FPGA link ([`protocol::fpga`]): the emulated [`Device`]
//! answering a controller that talks to it over a byte stream (a QEMU board's second UART).
//!
//! Sans-I/O like [`protocol::link`]: bytes in through [`FpgaServer::input`], bytes out
//! through [`FpgaServer::poll_transmit`], time passed in by the caller, so `fpgfx-sim` owns
//! the port and tests can drive it from memory.

use heapless::Vec;
use protocol::fpga::{
    Fault, FaultCode, FpgaReply, FpgaRequest, FpgaStatus, Identity, LayoutId, FPGA_SCHEMA_HASH,
};
use protocol::frame::{decode, encode, READ_CHUNK};
use protocol::link::{Event, Link};
use protocol::MAX_PAYLOAD;

use protocol::bus::MAX_RECORDS;

use crate::device::{Device, DeviceError};

/// The emulated FPGA behind a link.
pub struct FpgaServer {
    link: Link<8>,
    device: Device,
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

impl FpgaServer {
    /// Serves `device`.
    pub fn new(device: Device) -> Self {
        Self {
            link: Link::new(Default::default()),
            device,
            requests: 0,
            fault: None,
            fault_text: None,
            partial: None,
            outbox: Default::default(),
        }
    }

    /// The device behind the link, for a caller that inspects or resets it directly.
    pub fn device(&mut self) -> &mut Device {
        &mut self.device
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
        self.device.reset();
        self.requests = 0;
        self.fault = None;
        self.partial = None;
        self.outbox.clear();
    }

    /// Runs the FPGA for a while (executes queued FIFO packets); call it whenever the
    /// line is quiet. Returns whether there was work.
    pub fn work(&mut self) -> bool {
        if self.device.idle() {
            return false;
        }
        if let Err(e) = self.device.wait() {
            self.refuse(self.requests.saturating_sub(1), &e);
        }
        true
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

    fn refuse(&mut self, request: u32, e: &DeviceError) {
        let code = match e {
            DeviceError::Packet { .. } | DeviceError::Raster { .. } => FaultCode::Packet,
            DeviceError::Overrun { .. } => FaultCode::Overrun,
            DeviceError::Setup(_) | DeviceError::NoSetup(_) => FaultCode::Setup,
            DeviceError::Registers { .. } => FaultCode::OutOfRange,
            DeviceError::Scene(_) | DeviceError::Render(_) => FaultCode::Scene,
        };
        self.fault_code(request, code, e.to_string());
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
        let result = match req {
            FpgaRequest::Identify => {
                let layout = self.device.layout();
                match LayoutId::of(layout) {
                    Some(layout) => {
                        let caps = self.device.caps();
                        self.answer(FpgaReply::Identity(Identity {
                            schema_hash: FPGA_SCHEMA_HASH,
                            caps,
                            layout,
                        }));
                    }
                    None => self.fault_code(
                        index,
                        FaultCode::Setup,
                        format!("layout {} has no wire id", layout.name),
                    ),
                }
                Ok(())
            }
            FpgaRequest::Reset => {
                self.power_on();
                // The reset request itself is #0 of the new count.
                self.requests = 1;
                Ok(())
            }
            FpgaRequest::Status => {
                let done = self.device.poll_done();
                let status = FpgaStatus {
                    fifo_free: self.device.fifo_free().min(usize::from(u16::MAX)) as u16,
                    idle: self.device.idle(),
                    done,
                };
                self.answer(FpgaReply::Status(status));
                Ok(())
            }
            FpgaRequest::Push {
                channel,
                last,
                records,
            } => self.push(index, channel, last, &records),
            FpgaRequest::RasterSetup(s) => self.device.raster_setup(&s),
            FpgaRequest::Regs { offset, words } => self.device.write_regs(offset, &words),
            FpgaRequest::Texels { offset, bytes } => self.device.write_texels(offset, bytes),
            FpgaRequest::Start(s) => self.device.start(&s),
            FpgaRequest::Stop => Ok(()),
            FpgaRequest::ReadLen(r) => {
                let n = self.device.read_len(&r);
                self.answer(FpgaReply::ReadLen(n));
                Ok(())
            }
            FpgaRequest::Read { req, offset, len } => {
                let len = usize::from(len);
                let total = self.device.read_len(&req);
                let fits = len <= READ_CHUNK
                    && total.is_some_and(|t| u64::from(offset) + len as u64 <= u64::from(t));
                if fits {
                    let mut data: Vec<u8, READ_CHUNK> = Vec::new();
                    // len ≤ READ_CHUNK was checked above.
                    let _ = data.resize(len, 0);
                    self.device.read(&req, offset, &mut data);
                    self.answer(FpgaReply::Data(data));
                } else {
                    self.fault_code(
                        index,
                        FaultCode::OutOfRange,
                        format!("read of {len} bytes at {offset} outside the buffer ({total:?})"),
                    );
                    self.answer(FpgaReply::Data(Vec::new()));
                }
                Ok(())
            }
            FpgaRequest::Counters => {
                let c = self.device.counters();
                self.answer(FpgaReply::Counters(c));
                Ok(())
            }
        };
        if let Err(e) = result {
            self.refuse(index, &e);
        }
    }

    fn push(
        &mut self,
        index: u32,
        channel: u8,
        last: bool,
        records: &[u64],
    ) -> Result<(), DeviceError> {
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
        self.device.push_packet(ch, &buf)
    }
}
