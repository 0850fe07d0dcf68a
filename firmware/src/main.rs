//! The qgait hub: per-joint IMU angle packets in on the UART, pose frames out.

#![no_std]
#![no_main]

use core::mem::MaybeUninit;

use cortex_m_rt::entry;
use qgait_firmware::board::{Board, Serial, SysTickClock};
use qgait_firmware::{board, stack};
use qgait_hub::{Hub, DEFAULT_STATUS_PERIOD_MS};

/// The application: the hub on this board's UART and clock.
type AppHub = Hub<Serial, SysTickClock>;

#[entry]
fn main() -> ! {
    let hub = qgait_firmware::start!(
        init_hub,
        "qgait hub on {=str}, stack region {=u32} bytes (painted)",
        "hub state {=usize} bytes (static)"
    );
    serve(hub)
}

/// The main loop. Never inlined, so its frame (the per-poll temporaries) and `init_hub`'s are
/// never on the stack at the same time.
#[inline(never)]
fn serve(hub: &'static mut AppHub) -> ! {
    loop {
        // Busy polling: the UART has a one-byte buffer (CMSDK) or a six-byte FIFO (nRF52).
        let summary = hub.poll();
        if summary.status_sent {
            defmt::info!("status {}", hub.status());
            stack::log_peak();
        }
    }
}

/// Builds the hub into its static. A function of its own, never inlined, so the temporaries of
/// construction live in a stack frame that is gone before the main loop starts, and the hub
/// itself is not part of `main`'s frame.
#[inline(never)]
fn init_hub(board: Board) -> &'static mut AppHub {
    // The static starts uninitialised (no 4 KB value is moved into it) and `Hub::init` builds
    // the hub in it: only the model's chain is a temporary on the stack.
    let Some(slot) = cortex_m::singleton!(: MaybeUninit<AppHub> = MaybeUninit::uninit()) else {
        defmt::error!("the hub was built twice");
        board::exit(1)
    };
    match Hub::init(slot, board.serial, board.clock, DEFAULT_STATUS_PERIOD_MS) {
        Ok(hub) => hub,
        // PHAK with gait2392's lengths, which the hub's tests build: never refused. The error
        // is not logged: its `defmt::Format` would cost 252 B of flash for a path not taken.
        Err(_) => {
            defmt::error!("default model refused");
            board::exit(1)
        }
    }
}
