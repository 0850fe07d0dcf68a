//! A millisecond clock from the SysTick interrupt (both boards).

use core::sync::atomic::{AtomicU32, Ordering};

use cortex_m::peripheral::{syst::SystClkSource, SYST};
use cortex_m_rt::exception;
use qgait_hub::Clock;

static MILLIS: AtomicU32 = AtomicU32::new(0);

/// Reads the millisecond counter that the SysTick interrupt advances (owns SysTick).
pub struct SysTickClock {
    _syst: SYST,
}

impl SysTickClock {
    /// Starts SysTick on the core clock (`core_hz`), interrupting every millisecond.
    pub fn start(mut syst: SYST, core_hz: u32) -> SysTickClock {
        syst.set_clock_source(SystClkSource::Core);
        syst.set_reload(core_hz / 1000 - 1);
        syst.clear_current();
        syst.enable_interrupt();
        syst.enable_counter();
        SysTickClock { _syst: syst }
    }
}

impl Clock for SysTickClock {
    fn now_ms(&self) -> u32 {
        MILLIS.load(Ordering::Relaxed)
    }
}

#[exception]
fn SysTick() {
    MILLIS.fetch_add(1, Ordering::Relaxed);
}
