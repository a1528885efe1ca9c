//! OBU firmware for an STM32F405 (Cortex-M4F): the project's codec and OBU core fed from
//! serial ports, all memory static (no heap).
//!
//! * [`board`]: USARTs (receive interrupts into lock-free SPSC queues), SysTick clock, stack
//!   painting (the only `unsafe`).
//! * [`app`]: NMEA bytes -> fixes, V2X frames -> [`obu::Obu::on_datagram`], the core,
//!   `HmiState` frames out.
//!
//! Ports (QEMU's `-serial` options in this order): USART1 NMEA in, USART2 V2X frames in
//! (`obu::link` frames: COBS + CRC-32 around what the core's one receive path takes: a UPER
//! MessageFrame, bare or in a 1609.2 envelope, or an RSU text record), USART3 `HmiState` out (`obu::link` frames around postcard).
#![no_std]
#![deny(unsafe_code)]
#![warn(missing_docs)]

pub mod app;
pub mod board;

/// The IEEE 1609.2 trust built in at build time (`OBU_TRUST_ANCHORS`, `OBU_REQUIRE_SIGNED`;
/// default: the bench PKI's anchors, signatures required).
pub mod security {
    include!(concat!(env!("OUT_DIR"), "/trust_anchors.rs"));

    /// The core's security settings of this build.
    pub const CONFIG: obu::security::SecurityConfig = obu::security::SecurityConfig {
        require_signed: REQUIRE_SIGNED,
        ..obu::security::SecurityConfig::DEFAULT
    };

    /// Gives `msgs` this build's settings and anchors; returns how many anchors it took
    /// (an anchor it refuses is logged and left out).
    pub fn configure(msgs: &mut crate::app::Messages) -> usize {
        let trust = msgs.trust_mut();
        trust.set_config(CONFIG);
        let mut taken = 0;
        for anchor in TRUST_ANCHORS {
            match trust.add_anchor(anchor) {
                Ok(()) => taken += 1,
                Err(_) => defmt::error!("a built-in trust anchor was refused"),
            }
        }
        taken
    }
}

use obu::AlertConfig;

/// The alert settings of the firmware: the core's defaults (a 100 m warning, 9 s lead, the
/// paper's field test; see `obu::alert::settings`).
pub const CONFIG: AlertConfig = AlertConfig::DEFAULT;

/// Widens the 32-bit millisecond counter into the core's 64-bit `Instant`.
#[derive(Debug, Default)]
pub struct Clock {
    last: u32,
    high: u64,
}

impl Clock {
    /// A clock at the counter's current value.
    pub const fn new() -> Self {
        Self { last: 0, high: 0 }
    }

    /// The core's time for the counter value `ms`.
    pub fn now(&mut self, ms: u32) -> obu::Instant {
        if ms < self.last {
            self.high += 1 << 32;
        }
        self.last = ms;
        obu::Instant::from_millis(self.high + u64::from(ms))
    }
}

/// Reports a panic over defmt and stops with a failure (semihosting exit status 1 under
/// QEMU; a real board without a debugger halts in the loop of [`exit`]).
#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    defmt::error!("panic: {}", defmt::Display2Format(info));
    exit(false)
}

/// Ends the program: semihosting SYS_EXIT (QEMU or a debugger), then a breakpoint loop.
pub fn exit(success: bool) -> ! {
    let status = if success {
        cortex_m_semihosting::debug::EXIT_SUCCESS
    } else {
        cortex_m_semihosting::debug::EXIT_FAILURE
    };
    cortex_m_semihosting::debug::exit(status);
    loop {
        cortex_m::asm::bkpt();
    }
}

/// A hard fault (e.g. a bad register access) is reported like a panic.
#[cortex_m_rt::exception]
#[allow(unsafe_code)] // the attribute's expansion declares the handler `unsafe`
unsafe fn HardFault(frame: &cortex_m_rt::ExceptionFrame) -> ! {
    defmt::error!("hard fault at pc {=u32:#x}", frame.pc());
    exit(false)
}
