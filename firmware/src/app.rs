//! What the hub and the node do alike at start: take the board, log the start, build the
//! application into its static, log its size.

use crate::board::{self, Board};
use crate::stack;

/// Starts the application `name` (`"hub"`, `"node"`): the board's peripherals taken (or the run
/// ended), the start logged, `init` building the application into its static, its size logged.
/// Returns the application, for the main loop.
pub fn start<A>(name: &str, init: impl FnOnce(Board) -> &'static mut A) -> &'static mut A {
    let Some(board) = board::take() else {
        defmt::error!("board peripherals already taken");
        board::exit(1)
    };
    defmt::info!(
        "qgait {=str} on {=str}, stack region {=u32} bytes (painted)",
        name,
        board::NAME,
        stack::size()
    );
    let app = init(board);
    defmt::info!(
        "{=str} state {=usize} bytes (static)",
        name,
        core::mem::size_of_val(app)
    );
    app
}
