//! The STM32F405 hardware this firmware touches, and the only module with `unsafe`.
//!
//! * USART1..3 (SR/DR/BRR/CR1 of the STM32F2/F4 USART, as QEMU's `stm32f2xx_usart` emulates
//!   them), with their clocks (RCC) and pins (GPIO alternate function 7) for a real board:
//!   USART1 PA9/PA10, USART2 PA2/PA3, USART3 PB10/PB11. The two input ports receive in their
//!   interrupt (IRQ 37 and 38) into heapless's lock-free SPSC queues: at 115200 baud a byte comes every 87 us,
//!   far less than a MAP takes to decode, so a polled receiver would overrun; and the main
//!   loop can sleep (`wfi`) until a byte or the next millisecond tick.
//! * Back-pressure instead of loss: when a receive queue is full its interrupt leaves the byte
//!   in the data register and masks itself in the NVIC until the main loop has taken bytes
//!   out. With RTS flow control on (CR3 RTSE, USART1 RTS on PA12, USART2 RTS on PA1) the
//!   USART holds RTS off while that byte waits, so the sender pauses; QEMU's model stops
//!   reading its chardev while RXNE is set, which is the same pause. A link that bursts faster
//!   than the firmware decodes (a loaded host feeding QEMU, a sender without pauses) thus
//!   delays bytes but never drops them.
//! * The millisecond clock: SysTick at 1 kHz counting in an atomic.
//! * Stack painting: fill the unused stack with a pattern at boot, find the deepest use later.
//!
//! Every `unsafe` here is a volatile access to a fixed, documented register address (through
//! the `unsafe fn` helpers [`reg_read`], [`reg_write`], [`reg_modify`], whose `# Safety`
//! says what a caller guarantees), the one-time split of the receive queues, or the stack
//! region the linker script reserves; nothing else in the crate uses `unsafe`.
#![allow(unsafe_code)]

use core::cell::RefCell;
use core::convert::Infallible;
use core::ptr::{read_volatile, write_volatile};
use core::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use cortex_m::interrupt::Mutex;
use cortex_m::peripheral::{syst::SystClkSource, SYST};
use cortex_m_rt::exception;
use heapless::spsc::{Consumer, Producer, Queue};

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
const CR3: usize = 0x14;
/// CR3: RTS flow control (RTS off while a received byte waits in DR).
const CR3_RTSE: u32 = 1 << 8;
const SR_RXNE: u32 = 1 << 5;
const SR_ORE: u32 = 1 << 3;
const CR1_RXNEIE: u32 = 1 << 5;
/// NVIC interrupt set-enable registers.
const NVIC_ISER: usize = 0xE000_E100;
/// NVIC interrupt clear-enable registers.
const NVIC_ICER: usize = 0xE000_E180;
const SR_TXE: u32 = 1 << 7;
const SR_TC: u32 = 1 << 6;
const CR1_UE: u32 = 1 << 13;
const CR1_TE: u32 = 1 << 3;
const CR1_RE: u32 = 1 << 2;

/// Reads the 32-bit memory-mapped register at `addr`.
///
/// # Safety
///
/// `addr` must be the address of a readable, 4-byte aligned peripheral register of the
/// STM32F405 (one of the constants above, or a USART base plus one of its offsets) whose
/// read has no side effect other than those the caller intends (reading DR takes a byte).
unsafe fn reg_read(addr: usize) -> u32 {
    // SAFETY: the caller guarantees a valid register address (see `# Safety`).
    unsafe { read_volatile(addr as *const u32) }
}

/// Writes `value` to the 32-bit memory-mapped register at `addr`.
///
/// # Safety
///
/// As for [`reg_read`], for a writable register; and `value` must be a setting the caller
/// means (no Rust memory is behind these addresses, so nothing else can be invalidated).
unsafe fn reg_write(addr: usize, value: u32) {
    // SAFETY: the caller guarantees a valid register address (see `# Safety`).
    unsafe { write_volatile(addr as *mut u32, value) }
}

/// Read-modify-write of the register at `addr`.
///
/// # Safety
///
/// As for [`reg_read`] and [`reg_write`]; not atomic, so the register must not be written by
/// an interrupt at the same time (the firmware sets registers up before enabling them).
unsafe fn reg_modify(addr: usize, f: impl FnOnce(u32) -> u32) {
    // SAFETY: the caller's guarantees, passed on.
    unsafe { reg_write(addr, f(reg_read(addr))) }
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

    /// The RTS pin on GPIOA (input ports; STM32F405 datasheet, alternate function 7).
    fn rts_pin(self) -> Option<u32> {
        match self {
            Port::Usart1 => Some(12),
            Port::Usart2 => Some(1),
            Port::Usart3 => None,
        }
    }

    /// Masks (`false`) or unmasks (`true`) this port's interrupt in the NVIC.
    fn set_irq_enabled(self, enabled: bool) {
        let irq = usize::from(self.irq());
        let reg = if enabled { NVIC_ISER } else { NVIC_ICER };
        // SAFETY: the NVIC set/clear-enable register holding this interrupt's bit; writing
        // a one changes that interrupt only.
        unsafe { reg_write(reg + 4 * (irq / 32), 1 << (irq % 32)) };
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

/// A USART in 8N1 at [`BAUD`]; receiving through its interrupt and receive queue on the input
/// ports (USART1, USART2), polled on USART3; sending polled. `embedded-io`
/// [`Read`](embedded_io::Read) (blocking until a byte is there),
/// [`ReadReady`](embedded_io::ReadReady) and [`Write`](embedded_io::Write).
pub struct Usart {
    port: Port,
    base: usize,
    /// The consumer end of the port's receive queue (input ports).
    rx: Option<Consumer<'static, u8>>,
    /// Bytes taken from the receive queue so far (wraps at 4 GiB).
    taken: u32,
}

impl Usart {
    /// Sets up `port` (clock, pins, speed, receiver and transmitter); `None` if it was taken.
    pub fn take(port: Port) -> Option<Usart> {
        if port.taken().swap(true, Ordering::AcqRel) {
            return None;
        }
        let (enr, bit, gpio, tx, _) = port.wiring();
        let base = port.base();
        let rx = rx_queue(port).and_then(|q| q.take_consumer());
        // SAFETY: RCC, GPIO and USART registers of this chip at their reference-manual
        // addresses (`wiring`, `base`); the port was not taken before (the flag above), so
        // nothing else writes them, and its receive interrupt is enabled last.
        unsafe {
            reg_modify(RCC_AHB1ENR, |v| v | 0b11); // GPIOA, GPIOB
            reg_modify(enr, |v| v | (1 << bit));
            for (gpio, pin) in [(gpio, tx), (gpio, rx_pin(port))]
                .into_iter()
                .chain(port.rts_pin().map(|pin| (GPIOA, pin)))
            {
                reg_modify(gpio, |v| (v & !(0b11 << (2 * pin))) | (0b10 << (2 * pin)));
                let (afr, shift) = (gpio + 0x20 + 4 * (pin as usize / 8), 4 * (pin % 8));
                reg_modify(afr, |v| (v & !(0xF << shift)) | (7 << shift));
            }
            reg_write(base + BRR, SYSCLK_HZ.div_ceil(BAUD));
            if port.rts_pin().is_some() {
                reg_write(base + CR3, CR3_RTSE);
            }
            let rx_irq = if rx.is_some() { CR1_RXNEIE } else { 0 };
            reg_write(base + CR1, CR1_UE | CR1_TE | CR1_RE | rx_irq);
        }
        if rx.is_some() {
            port.set_irq_enabled(true);
        }
        Some(Usart {
            port,
            base,
            rx,
            taken: 0,
        })
    }

    fn status(&self) -> u32 {
        // SAFETY: the status register of this USART; reading it has no side effect.
        unsafe { reg_read(self.base + SR) }
    }

    /// The next received byte, if one is waiting.
    pub fn try_read_byte(&mut self) -> Option<u8> {
        match &mut self.rx {
            Some(rx) => {
                let byte = rx.dequeue()?;
                self.taken = self.taken.wrapping_add(1);
                // A slot is free again: let a paused receive interrupt take the waiting byte.
                if rx_queue(self.port).is_some_and(|q| q.resume()) {
                    self.port.set_irq_enabled(true);
                }
                Some(byte)
            }
            // SAFETY: this USART's data register, read once RXNE says a byte is there.
            None => {
                (self.status() & SR_RXNE != 0).then(|| unsafe { reg_read(self.base + DR) } as u8)
            }
        }
    }

    /// Bytes received and taken out of the receive queue so far (wraps at 4 GiB): a bench
    /// that knows what it sent tells from it when the firmware has caught up.
    pub fn rx_taken(&self) -> u32 {
        self.taken
    }

    /// Received bytes lost so far: the receiver overran (a byte came while the previous one
    /// still waited with flow control off). A full queue pauses the link, it loses nothing.
    pub fn rx_lost(&self) -> u32 {
        rx_queue(self.port).map_or(0, |q| q.lost.load(Ordering::Relaxed))
    }
}

/// The RX pin of `port` (the last of its wiring).
fn rx_pin(port: Port) -> u32 {
    port.wiring().4
}

/// The two ends of a receive queue until each is taken.
type QueueEnds = (Option<Producer<'static, u8>>, Option<Consumer<'static, u8>>);

/// An input port's receive queue: heapless's lock-free single-producer single-consumer
/// queue, the producer in the receive interrupt and the consumer in the main loop's
/// [`Usart`]. Each end is handed out once (under a critical section); after that neither
/// side takes a lock.
struct RxQueue {
    ends: Mutex<RefCell<QueueEnds>>,
    lost: AtomicU32,
    /// The queue was full: the receive interrupt masked itself, a byte waits in DR.
    paused: AtomicBool,
}

impl RxQueue {
    const fn new(producer: Producer<'static, u8>, consumer: Consumer<'static, u8>) -> Self {
        Self {
            ends: Mutex::new(RefCell::new((Some(producer), Some(consumer)))),
            lost: AtomicU32::new(0),
            paused: AtomicBool::new(false),
        }
    }

    /// True once after the interrupt paused on a full queue (the caller unmasks it).
    fn resume(&self) -> bool {
        self.paused.swap(false, Ordering::AcqRel)
    }

    fn take_consumer(&self) -> Option<Consumer<'static, u8>> {
        cortex_m::interrupt::free(|cs| self.ends.borrow(cs).borrow_mut().1.take())
    }

    fn take_producer(&self) -> Option<Producer<'static, u8>> {
        cortex_m::interrupt::free(|cs| self.ends.borrow(cs).borrow_mut().0.take())
    }

    /// Moves what the USART of `port` received into the queue (in its interrupt). On a full
    /// queue the byte stays in DR and the interrupt masks itself until [`Self::resume`].
    fn fill(&self, producer: &mut Producer<'static, u8>, port: Port) {
        let base = port.base();
        loop {
            if !producer.ready() {
                // Masked before the flag is set; the main loop, which cannot preempt this
                // handler, sees both or neither.
                port.set_irq_enabled(false);
                self.paused.store(true, Ordering::Release);
                break;
            }
            // SAFETY: the status and data registers of the USART this queue belongs to;
            // reading SR then DR takes the byte and clears RXNE and an overrun flag.
            let (sr, byte) = unsafe {
                let sr = reg_read(base + SR);
                if sr & SR_RXNE == 0 {
                    break;
                }
                (sr, reg_read(base + DR) as u8)
            };
            let overrun = u32::from(sr & SR_ORE != 0);
            // `ready()` above: the queue has room for this byte.
            let full = u32::from(producer.enqueue(byte).is_err());
            self.lost.fetch_add(overrun + full, Ordering::Relaxed);
        }
    }
}

/// A queue of `N - 1` bytes, split once at compile time into its two ends.
macro_rules! rx_queue {
    ($n:literal) => {{
        static mut QUEUE: Queue<u8, $n> = Queue::new();
        // SAFETY: `QUEUE` is named only here, in this static's initializer, which runs once
        // (at compile time): its two ends are the only references to it.
        #[allow(static_mut_refs)]
        let (producer, consumer) = unsafe { QUEUE.split_const() };
        RxQueue::new(producer, consumer)
    }};
}

/// NMEA: 511 bytes are 44 ms at 115200 baud, many times the longest pause of the main loop
/// (a MAP decode, a few milliseconds).
static RX_NMEA: RxQueue = rx_queue!(512);
/// V2X: 1023 bytes are 89 ms at 115200 baud; the loop drains it into the deframer between
/// messages, so a frame longer than the queue still arrives whole.
static RX_V2X: RxQueue = rx_queue!(1024);

fn rx_queue(port: Port) -> Option<&'static RxQueue> {
    match port {
        Port::Usart1 => Some(&RX_NMEA),
        Port::Usart2 => Some(&RX_V2X),
        Port::Usart3 => None,
    }
}

/// The device interrupts: the input USARTs' receive interrupts fill their queues; nothing
/// else is enabled.
#[exception]
unsafe fn DefaultHandler(irqn: i16) {
    // The producers, taken from their queues on the first interrupt of each port.
    static mut PRODUCERS: [Option<Producer<'static, u8>>; 2] = [None, None];
    for (i, port) in [Port::Usart1, Port::Usart2].into_iter().enumerate() {
        if i32::from(irqn) != i32::from(port.irq()) {
            continue;
        }
        let Some(queue) = rx_queue(port) else {
            continue;
        };
        if PRODUCERS[i].is_none() {
            PRODUCERS[i] = queue.take_producer();
        }
        if let Some(producer) = &mut PRODUCERS[i] {
            queue.fill(producer, port);
        }
    }
}

/// Sleeps until an interrupt (a received byte or the millisecond tick).
pub fn wait_for_interrupt() {
    cortex_m::asm::wfi();
}

impl core::fmt::Debug for Usart {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Usart")
            .field("port", &self.port)
            .field("base", &self.base)
            .field("receive_queue", &self.rx.is_some())
            .finish()
    }
}

impl embedded_io::ErrorType for Usart {
    type Error = Infallible;
}

impl embedded_io::ReadReady for Usart {
    fn read_ready(&mut self) -> Result<bool, Infallible> {
        Ok(match &self.rx {
            Some(rx) => rx.ready(),
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
            // SAFETY: this USART's data register, written once TXE says it is empty.
            unsafe { reg_write(self.base + DR, u32::from(b)) };
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
