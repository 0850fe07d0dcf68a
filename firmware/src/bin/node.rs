//! The qgait IMU node: raw samples in on the UART (its sensor's FIFO; under QEMU streamed by
//! the host), fused by the kernel's VQF in `f32`, segment orientations out (`qgait-node`).

#![no_std]
#![no_main]

use core::mem::MaybeUninit;

use cortex_m_rt::entry;
use qgait_firmware::board::{Board, Serial, SysTickClock};
use qgait_firmware::{board, stack};
use qgait_node::{Node, DEFAULT_STATUS_PERIOD_MS};

/// The application: the node on this board's UART and clock.
type AppNode = Node<Serial, SysTickClock>;

#[entry]
fn main() -> ! {
    let node = qgait_firmware::start!(
        init_node,
        "qgait node on {=str}, stack region {=u32} bytes (painted)",
        "node state {=usize} bytes (static)"
    );
    serve(node)
}

/// The main loop. Never inlined, so its frame and `init_node`'s are never on the stack at the
/// same time.
#[inline(never)]
fn serve(node: &'static mut AppNode) -> ! {
    loop {
        let summary = node.poll();
        // The counters themselves go out on the UART (`Status`, `RawImuStatus`): the log has
        // only what the UART cannot say (formatting `Status` here would cost 0.2 KB of flash).
        if summary.status_sent {
            stack::log_peak();
        }
    }
}

/// Builds the node into its static, in a frame of its own that is gone before the main loop.
#[inline(never)]
fn init_node(board: Board) -> &'static mut AppNode {
    let Some(slot) = cortex_m::singleton!(: MaybeUninit<AppNode> = MaybeUninit::uninit()) else {
        defmt::error!("the node was built twice");
        board::exit(1)
    };
    slot.write(Node::new(
        board.serial,
        board.clock,
        DEFAULT_STATUS_PERIOD_MS,
    ))
}
