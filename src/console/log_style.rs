//! How the controller's log lines look on the console: plain lines on stderr, like the
//! console's own, so that they read as part of the run's story and never interleave
//! timestamps and levels with the status lines on stdout. And the console's FAULT line.

use std::fmt;

use crate::state::fault_advice::CameBack;
use crate::state::status::FaultRecord;

use tracing::{Event, Level, Subscriber};
use tracing_subscriber::fmt::format::Writer;
use tracing_subscriber::fmt::{FmtContext, FormatEvent, FormatFields};
use tracing_subscriber::registry::LookupSpan;

/// `warning: ...` and `error: ...` for the lines a user must act on, the bare message
/// for the rest (a camera link opened, a card found).
pub(crate) struct Plain;

impl<S, N> FormatEvent<S, N> for Plain
where
    S: Subscriber + for<'a> LookupSpan<'a>,
    N: for<'a> FormatFields<'a> + 'static,
{
    fn format_event(
        &self,
        ctx: &FmtContext<'_, S, N>,
        mut writer: Writer<'_>,
        event: &Event<'_>,
    ) -> fmt::Result {
        match *event.metadata().level() {
            Level::ERROR => write!(writer, "error: ")?,
            Level::WARN => write!(writer, "warning: ")?,
            _ => {}
        }
        ctx.field_format().format_fields(writer.by_ref(), event)?;
        writeln!(writer)
    }
}

/// Send the log lines to stderr in the plain style. The bus's library (zenoh) speaks
/// only of errors: its notes on sessions and gossip mean nothing to a field scientist,
/// and the bus says in its own words what it does.
pub fn init() {
    use tracing_subscriber::filter::{LevelFilter, Targets};
    use tracing_subscriber::prelude::*;
    let filter = Targets::new()
        .with_target(
            "zenoh",
            if std::env::var_os("MECHWEED_ZENOH_DEBUG").is_some() {
                LevelFilter::DEBUG
            } else {
                LevelFilter::ERROR
            },
        )
        .with_default(LevelFilter::INFO);
    let layer = tracing_subscriber::fmt::layer()
        .with_writer(std::io::stderr)
        .with_ansi(false)
        .event_format(Plain)
        .with_filter(filter);
    tracing_subscriber::registry().with(layer).init();
}

/// The console's line for a fault: when, the cause, whether it came back after a
/// power-up, and what to check, all on one line, so that a log searched for FAULT
/// gives the advice with it.
pub(crate) fn fault_line(fault: &FaultRecord) -> String {
    let came_back = match fault.came_back_after_s {
        Some(after_s) => format!("; {}", CameBack { after_s }),
        None => String::new(),
    };
    format!(
        "{:7.2} s  FAULT: {}{came_back}; what to check: {}",
        fault.t_s,
        fault.cause,
        fault.cause.what_to_check()
    )
}

#[cfg(test)]
mod tests {
    use mechweed_hw::EncoderId;

    use super::*;
    use crate::state::fault_cause::FaultCause;

    #[test]
    fn the_fault_line_says_what_to_check_and_that_the_fault_came_back() {
        let mut fault = FaultRecord {
            cause: FaultCause::EncoderStuck(EncoderId::Left),
            t_s: 12.5,
            tick_seen: 1250,
            tick_safe: 1250,
            came_back_after_s: None,
        };
        assert_eq!(
            fault_line(&fault),
            "  12.50 s  FAULT: left wheel encoder does not count while its motor is driven; what to check: the encoder and its cable, then Power up"
        );
        fault.came_back_after_s = Some(0.6);
        let again = fault_line(&fault);
        assert!(
            again.contains("driven; came back 0.6 s after power-up: its cause is still there, check again; what to check: the encoder and its cable"),
            "{again}"
        );
    }
}
