//! The STM32F405 hardware this firmware touches, and the only module with `unsafe`.
//!
//! * USART1..3 (SR/DR/BRR/CR1 of the STM32F2/F4 USART, as QEMU's `stm32f2xx_usart` emulates
//!   them), with their clocks (RCC) and pins (GPIO alternate function 7) for a real board:
//!   USART1 PA9/PA10, USART2 PA2/PA3, USART3 PB10/PB11. The two input ports receive in their
//!   interrupt (IRQ 37 and 38) into ring buffers: at 115200 baud a byte comes every 87 us,
//!   far less than a MAP takes to decode, so a polled receiver would overrun; and the main
//!   loop can sleep (`wfi`) until a byte or the next millisecond tick.
//! * The millisecond clock: SysTick at 1 kHz counting in an atomic.
//! * Stack painting: fill the unused stack with a pattern at boot, find the deepest use later.
//!
//! Every `unsafe` here is a volatile access to a fixed, documented register address or to the
//! stack region the linker script reserves; nothing else in the crate uses `unsafe`.
#![allow(unsafe_code)]

use core::convert::Infallible;
use core::ptr::{read_volatile, write_volatile};
use core::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use cortex_m::peripheral::{syst::SystClkSource, SYST};
use cortex_m_rt::exception;

/// Core clock in Hz: the STM32F405's 16 MHz HSI after reset (no PLL set up), or the 168 MHz
/// QEMU's `netduinoplus2` models (feature `qemu`).
pub const SYSCLK_HZ: u32 = if cfg!(feature = "qemu") {
    168_000_000
} else {
    16_000_000
};
/// Serial speed of the three ports.
pub const BAUD: u32 = 115_200;

const RCC: usize = 0x4002_3800;
const RCC_AHB1ENR: usize = RCC + 0x30;
const RCC_APB1ENR: usize = RCC + 0x40;
const RCC_APB2ENR: usize = RCC + 0x44;
const GPIOA: usize = 0x4002_0000;
const GPIOB: usize = 0x4002_0400;

const SR: usize = 0x00;
const DR: usize = 0x04;
const BRR: usize = 0x08;
const CR1: usize = 0x0C;
const SR_RXNE: u32 = 1 << 5;
const SR_ORE: u32 = 1 << 3;
const CR1_RXNEIE: u32 = 1 << 5;
/// NVIC interrupt set-enable registers.
const NVIC_ISER: usize = 0xE000_E100;
const SR_TXE: u32 = 1 << 7;
const SR_TC: u32 = 1 << 6;
const CR1_UE: u32 = 1 << 13;
const CR1_TE: u32 = 1 << 3;
const CR1_RE: u32 = 1 << 2;

fn reg_read(addr: usize) -> u32 {
    // SAFETY: `addr` is one of the aligned peripheral registers named above.
    unsafe { read_volatile(addr as *const u32) }
}

fn reg_write(addr: usize, value: u32) {
    // SAFETY: as in `reg_read`; the peripheral registers have no Rust-visible aliasing.
    unsafe { write_volatile(addr as *mut u32, value) }
}

fn reg_modify(addr: usize, f: impl FnOnce(u32) -> u32) {
    reg_write(addr, f(reg_read(addr)));
}

/// One of the three USARTs the firmware uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, defmt::Format)]
pub enum Port {
    /// USART1 (QEMU's first `-serial`): NMEA in.
    Usart1,
    /// USART2 (second `-serial`): V2X frames in.
    Usart2,
    /// USART3 (third `-serial`): HmiState out.
    Usart3,
}

impl Port {
    fn base(self) -> usize {
        match self {
            Port::Usart1 => 0x4001_1000,
            Port::Usart2 => 0x4000_4400,
            Port::Usart3 => 0x4000_4800,
        }
    }

    /// Clock enable (register, bit), GPIO port, TX pin, RX pin.
    fn wiring(self) -> (usize, u32, usize, u32, u32) {
        match self {
            Port::Usart1 => (RCC_APB2ENR, 4, GPIOA, 9, 10),
            Port::Usart2 => (RCC_APB1ENR, 17, GPIOA, 2, 3),
            Port::Usart3 => (RCC_APB1ENR, 18, GPIOB, 10, 11),
        }
    }

    /// Interrupt number (STM32F405 reference manual, vector table).
    fn irq(self) -> u16 {
        match self {
            Port::Usart1 => 37,
            Port::Usart2 => 38,
            Port::Usart3 => 39,
        }
    }

    fn taken(self) -> &'static AtomicBool {
        static TAKEN: [AtomicBool; 3] = [const { AtomicBool::new(false) }; 3];
        &TAKEN[self as usize]
    }
}

/// A USART in 8N1 at [`BAUD`]; receiving through its interrupt and ring buffer on the input
/// ports (USART1, USART2), polled on USART3; sending polled. `embedded-io`
/// [`Read`](embedded_io::Read) (blocking until a byte is there),
/// [`ReadReady`](embedded_io::ReadReady) and [`Write`](embedded_io::Write).
#[derive(Debug)]
pub struct Usart {
    port: Port,
    base: usize,
}

impl Usart {
    /// Sets up `port` (clock, pins, speed, receiver and transmitter); `None` if it was taken.
    pub fn take(port: Port) -> Option<Usart> {
        if port.taken().swap(true, Ordering::AcqRel) {
            return None;
        }
        let (enr, bit, gpio, tx, rx) = port.wiring();
        reg_modify(RCC_AHB1ENR, |v| v | 0b11); // GPIOA, GPIOB
        reg_modify(enr, |v| v | (1 << bit));
        for pin in [tx, rx] {
            reg_modify(gpio, |v| (v & !(0b11 << (2 * pin))) | (0b10 << (2 * pin)));
            let (afr, shift) = (gpio + 0x20 + 4 * (pin as usize / 8), 4 * (pin % 8));
            reg_modify(afr, |v| (v & !(0xF << shift)) | (7 << shift));
        }
        let base = port.base();
        reg_write(base + BRR, SYSCLK_HZ.div_ceil(BAUD));
        let rx_irq = if rx_ring(port).is_some() {
            CR1_RXNEIE
        } else {
            0
        };
        reg_write(base + CR1, CR1_UE | CR1_TE | CR1_RE | rx_irq);
        if rx_irq != 0 {
            let irq = usize::from(port.irq());
            reg_write(NVIC_ISER + 4 * (irq / 32), 1 << (irq % 32));
        }
        Some(Usart { port, base })
    }

    fn status(&self) -> u32 {
        reg_read(self.base + SR)
    }

    /// The next received byte, if one is waiting.
    pub fn try_read_byte(&mut self) -> Option<u8> {
        match rx_ring(self.port) {
            Some(ring) => ring.pop(),
            None => (self.status() & SR_RXNE != 0).then(|| reg_read(self.base + DR) as u8),
        }
    }

    /// Received bytes lost so far: ring buffer full, or the receiver overrun.
    pub fn rx_lost(&self) -> u32 {
        rx_ring(self.port).map_or(0, |r| r.lost().load(Ordering::Relaxed))
    }
}

/// Bytes received in an interrupt, waiting for the main loop.
struct RxRing<const N: usize> {
    bytes: cortex_m::interrupt::Mutex<core::cell::RefCell<heapless::Deque<u8, N>>>,
    lost: AtomicU32,
}

impl<const N: usize> RxRing<N> {
    const fn new() -> Self {
        Self {
            bytes: cortex_m::interrupt::Mutex::new(
                core::cell::RefCell::new(heapless::Deque::new()),
            ),
            lost: AtomicU32::new(0),
        }
    }

    /// Moves what the USART at `base` received into the ring (in its interrupt).
    fn fill(&self, base: usize) {
        cortex_m::interrupt::free(|cs| {
            let mut q = self.bytes.borrow(cs).borrow_mut();
            loop {
                let sr = reg_read(base + SR);
                if sr & SR_RXNE == 0 {
                    break;
                }
                // Reading SR then DR clears RXNE and an overrun flag.
                let byte = reg_read(base + DR) as u8;
                let overrun = u32::from(sr & SR_ORE != 0);
                let full = u32::from(q.push_back(byte).is_err());
                self.lost.fetch_add(overrun + full, Ordering::Relaxed);
            }
        });
    }

    fn pop(&self) -> Option<u8> {
        cortex_m::interrupt::free(|cs| self.bytes.borrow(cs).borrow_mut().pop_front())
    }
}

/// The ring buffer behind an input port's interrupt, as a trait object over its size.
trait Ring: Sync {
    fn fill(&self, base: usize);
    fn pop(&self) -> Option<u8>;
    fn is_empty(&self) -> bool;
    fn lost(&self) -> &AtomicU32;
}

impl<const N: usize> Ring for RxRing<N> {
    fn fill(&self, base: usize) {
        RxRing::fill(self, base)
    }
    fn pop(&self) -> Option<u8> {
        RxRing::pop(self)
    }
    fn is_empty(&self) -> bool {
        cortex_m::interrupt::free(|cs| self.bytes.borrow(cs).borrow().is_empty())
    }
    fn lost(&self) -> &AtomicU32 {
        &self.lost
    }
}

/// NMEA: 512 bytes are 44 ms at 115200 baud, many times the longest pause of the main loop
/// (a MAP decode, a few milliseconds).
static RX_NMEA: RxRing<512> = RxRing::new();
/// V2X: 1 KiB is 89 ms at 115200 baud; the loop drains it into the deframer between
/// messages, so a frame longer than the ring still arrives whole.
static RX_V2X: RxRing<1024> = RxRing::new();

fn rx_ring(port: Port) -> Option<&'static dyn Ring> {
    match port {
        Port::Usart1 => Some(&RX_NMEA),
        Port::Usart2 => Some(&RX_V2X),
        Port::Usart3 => None,
    }
}

/// The device interrupts: the input USARTs' receive interrupts fill their rings; nothing else
/// is enabled.
#[exception]
unsafe fn DefaultHandler(irqn: i16) {
    for port in [Port::Usart1, Port::Usart2] {
        if i32::from(irqn) == i32::from(port.irq()) {
            if let Some(ring) = rx_ring(port) {
                ring.fill(port.base());
            }
        }
    }
}

/// Sleeps until an interrupt (a received byte or the millisecond tick).
pub fn wait_for_interrupt() {
    cortex_m::asm::wfi();
}

impl embedded_io::ErrorType for Usart {
    type Error = Infallible;
}

impl embedded_io::ReadReady for Usart {
    fn read_ready(&mut self) -> Result<bool, Infallible> {
        Ok(match rx_ring(self.port) {
            Some(ring) => !ring.is_empty(),
            None => self.status() & SR_RXNE != 0,
        })
    }
}

impl embedded_io::Read for Usart {
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, Infallible> {
        if buf.is_empty() {
            return Ok(0);
        }
        let mut n = 0;
        while n == 0 || n < buf.len() {
            match self.try_read_byte() {
                Some(b) => {
                    buf[n] = b;
                    n += 1;
                }
                None if n > 0 => break,
                None => {}
            }
        }
        Ok(n)
    }
}

impl embedded_io::Write for Usart {
    fn write(&mut self, buf: &[u8]) -> Result<usize, Infallible> {
        for &b in buf {
            while self.status() & SR_TXE == 0 {}
            reg_write(self.base + DR, u32::from(b));
        }
        Ok(buf.len())
    }

    fn flush(&mut self) -> Result<(), Infallible> {
        while self.status() & SR_TC == 0 {}
        Ok(())
    }
}

static MILLIS: AtomicU32 = AtomicU32::new(0);

/// Starts the 1 kHz SysTick that drives [`millis`].
pub fn start_clock(mut syst: SYST) {
    syst.set_clock_source(SystClkSource::Core);
    syst.set_reload(SYSCLK_HZ / 1000 - 1);
    syst.clear_current();
    syst.enable_interrupt();
    syst.enable_counter();
}

/// Milliseconds since [`start_clock`] (wraps after 49 days; the caller widens it).
pub fn millis() -> u32 {
    MILLIS.load(Ordering::Relaxed)
}

#[exception]
fn SysTick() {
    MILLIS.fetch_add(1, Ordering::Relaxed);
}

const PAINT: u32 = 0xC0FF_EE55;

extern "C" {
    // cortex-m-rt's linker script: the stack runs from `_stack_start` (top of RAM) down to
    // `_stack_end` (the end of the statics).
    static _stack_start: u32;
    static _stack_end: u32;
}

fn stack_bounds() -> (usize, usize) {
    // Only the addresses of the linker symbols are taken, never their contents.
    (
        core::ptr::addr_of!(_stack_end) as usize,
        core::ptr::addr_of!(_stack_start) as usize,
    )
}

/// Fills the stack below the current stack pointer (less a margin) with a pattern.
#[inline(never)]
pub fn paint_stack() {
    let (bottom, _) = stack_bounds();
    let sp = cortex_m::register::msp::read() as usize - 256;
    let mut at = bottom;
    while at < sp {
        // SAFETY: [bottom, sp) is the unused part of the stack region (linker script).
        unsafe { write_volatile(at as *mut u32, PAINT) };
        at += 4;
    }
}

/// (Deepest stack use in bytes since [`paint_stack`], stack size in bytes).
pub fn stack_high_water() -> (usize, usize) {
    let (bottom, top) = stack_bounds();
    let mut at = bottom;
    // SAFETY: reads within the stack region, below the live frames.
    while at < top && unsafe { read_volatile(at as *const u32) } == PAINT {
        at += 4;
    }
    (top - at, top - bottom)
}

/// Bytes of the stack region still holding the paint (a cross-check of [`stack_high_water`]:
/// a frame may skip words, so untouched words can lie below the high-water mark).
pub fn stack_untouched() -> usize {
    let (bottom, top) = stack_bounds();
    let mut n = 0;
    let mut at = bottom;
    while at < top {
        // SAFETY: reads within the stack region.
        n += usize::from(unsafe { read_volatile(at as *const u32) } == PAINT) * 4;
        at += 4;
    }
    n
}
