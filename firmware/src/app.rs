//! The start the hub and the node share: [`start!`](crate::start).

/// Starts an application (the hub, the node): the board's peripherals taken (or the run
/// ended), `$started` logged with the board's name and the stack region's size, `$init`
/// building the application into its static from the board, `$state` logged with the
/// application's size; evaluates to the application, for the main loop. A macro, not a
/// function, so that each binary's log lines stay literal format strings: a name passed as a
/// `str` would be encoded at run time (52 B more flash, measured with `cargo xtask footprint`).
#[macro_export]
macro_rules! start {
    ($init:expr, $started:tt, $state:tt) => {{
        let Some(board) = $crate::board::take() else {
            defmt::error!("board peripherals already taken");
            $crate::board::exit(1)
        };
        defmt::info!($started, $crate::board::NAME, $crate::stack::size());
        let app = $init(board);
        defmt::info!($state, core::mem::size_of_val(app));
        app
    }};
}
