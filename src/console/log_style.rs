//! How the controller's log lines look on the console: plain lines on stderr, like the
//! console's own, so that they read as part of the run's story and never interleave
//! timestamps and levels with the status lines on stdout.

use std::fmt;

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
