//! The firmware image: USART1 NMEA in, USART2 V2X frames in, USART3 `HmiState` out.
#![no_std]
#![no_main]
#![forbid(unsafe_code)]

use cortex_m_rt::entry;
use defmt_semihosting as _;
use embedded_io::{Read, ReadReady};
use obu_firmware::app::{send_state, Firmware, Messages, ShowCounters};
use obu_firmware::board::{self, Port, Usart};
use obu_firmware::{Clock, CONFIG};

/// The status report's period: counters, bytes taken and lost per input (NMEA/V2X), stack.
/// Every report follows a full pass over both inputs, so a bench that knows how many bytes
/// it sent reads from the "rx taken" figures when everything has been worked through.
const REPORT_PERIOD_MS: u64 = 1_000;

#[entry]
fn main() -> ! {
    // `static mut` in the entry function is handed out once as `&'static mut` (cortex-m-rt).
    static mut FIRMWARE: Firmware = Firmware::new(CONFIG);
    static mut MESSAGES: Messages = Messages::new();
    let fw: &'static mut Firmware = FIRMWARE;
    let msgs: &'static mut Messages = MESSAGES;
    let anchors = obu_firmware::security::configure(msgs);
    board::paint_stack();
    let Some(core) = cortex_m::Peripherals::take() else {
        obu_firmware::exit(false);
    };
    board::start_clock(core.SYST);
    let (Some(mut nmea), Some(mut v2x), Some(mut hmi)) = (
        Usart::take(Port::Usart1),
        Usart::take(Port::Usart2),
        Usart::take(Port::Usart3),
    ) else {
        obu_firmware::exit(false);
    };
    defmt::info!(
        "obu-firmware: state {=usize} B + messages {=usize} B; NMEA USART1, V2X USART2, HMI USART3; {=usize} trust anchors, signatures required: {=bool}",
        core::mem::size_of::<Firmware>(),
        core::mem::size_of::<Messages>(),
        anchors,
        obu_firmware::security::REQUIRE_SIGNED
    );
    let mut clock = Clock::new();
    let mut last_report = 0u64;
    loop {
        let now = clock.now(board::millis());
        let mut idle = true;
        let mut buf = [0u8; 64];
        // Both inputs through `embedded-io`: what the receive interrupts have buffered.
        while let Some(bytes) = received(&mut nmea, &mut buf) {
            idle = false;
            for &b in bytes {
                if let Some(state) = fw.on_gnss_byte(now, b) {
                    fw.hmi_dropped += u32::from(!send_state(&mut hmi, &state));
                }
            }
        }
        while let Some(bytes) = received(&mut v2x, &mut buf) {
            idle = false;
            for &b in bytes {
                if let Some(state) = fw.on_v2x_byte(msgs, now, b) {
                    fw.hmi_dropped += u32::from(!send_state(&mut hmi, &state));
                }
            }
        }
        if let Some(state) = fw.poll(now) {
            fw.hmi_dropped += u32::from(!send_state(&mut hmi, &state));
        }
        if now.millis() >= last_report + REPORT_PERIOD_MS {
            last_report = now.millis();
            let (used, size) = board::stack_high_water();
            defmt::info!(
                "t={=u64} ms v2x {} nmea errors {=u32} rx taken {=u32}/{=u32} B lost {=u32}/{=u32} stack {=usize}/{=usize} B",
                now.millis(),
                ShowCounters(&fw.v2x_counters),
                fw.nmea_errors,
                nmea.rx_taken(),
                v2x.rx_taken(),
                nmea.rx_lost(),
                v2x.rx_lost(),
                used,
                size
            );
        }
        if idle {
            // Nothing received: sleep until a byte or the next millisecond tick.
            board::wait_for_interrupt();
        }
    }
}

/// The bytes `port` has received, read into `buf` without blocking; `None` when there are
/// none.
fn received<'a, P: ReadReady + Read>(port: &mut P, buf: &'a mut [u8]) -> Option<&'a [u8]> {
    if !port.read_ready().unwrap_or(false) {
        return None;
    }
    let n = port.read(buf).unwrap_or(0);
    (n > 0).then_some(&buf[..n])
}
