//! `envmap demo`: every representation of the built-in sky side by side.

mod lit;
mod scene;

use std::io::Write;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};

use crate::args::CliResult;

#[derive(Args)]
pub(crate) struct DemoArgs {
    /// Output directory.
    #[arg(long, default_value = "envmap-demo")]
    pub(crate) out: PathBuf,
    /// Texel budget per representation, in thousands.
    #[arg(long, default_value_t = 393)]
    pub(crate) ktexels: u64,
    /// Render width in pixels (height is 3/4 of it).
    #[arg(long, default_value_t = 480)]
    pub(crate) width: u32,
    /// Supersampling of the renders (N×N).
    #[arg(long, default_value_t = 2)]
    pub(crate) samples: u32,
    /// Samples per pixel and per strategy of the lit section's Monte Carlo references.
    #[arg(long, default_value_t = 64)]
    pub(crate) reference_samples: u32,
    /// Leave out the lit section (materials by the split sum against the reference).
    #[arg(long)]
    pub(crate) no_lit: bool,
    /// No progress bar.
    #[arg(long, short)]
    pub(crate) quiet: bool,
}

pub(crate) fn run(a: &DemoArgs, stop: &AtomicBool) -> CliResult {
    if a.ktexels == 0
        || a.ktexels > 100_000
        || a.width < 16
        || a.width > 8192
        || a.samples == 0
        || a.samples > 8
        || a.reference_samples == 0
        || a.reference_samples > 65_536
    {
        return Err(
            "--ktexels 1..100000, --width 16..8192, --samples 1..8, --reference-samples 1..65536"
                .into(),
        );
    }
    let opts = crate::demo::scene::DemoOptions {
        out: a.out.clone(),
        texels: a.ktexels * 1000,
        width: a.width,
        samples: a.samples,
        lit: !a.no_lit,
        reference_samples: a.reference_samples,
        cancel: Some(stop),
        ..crate::demo::scene::DemoOptions::default()
    };
    let bar = if a.quiet {
        ProgressBar::hidden()
    } else {
        let b = ProgressBar::new(1);
        b.set_style(
            ProgressStyle::with_template("{msg:>24} [{bar:30}] {pos}/{len} ({elapsed})")
                .unwrap_or_else(|_| ProgressStyle::default_bar())
                .progress_chars("=> "),
        );
        b
    };
    let t = Instant::now();
    let report = crate::demo::scene::run(&opts, &|done, total, what| {
        bar.set_length(u64::from(total));
        bar.set_position(u64::from(done));
        bar.set_message(what.to_owned());
    })?;
    bar.finish_and_clear();
    // The report is written (report.md); a standard output that cannot take
    // it (closed early: `envmap demo | head`) is said, not a panic.
    let mut out = std::io::stdout().lock();
    let lit = if report.lit.is_empty() {
        String::new()
    } else {
        format!("\n{}", crate::demo::lit::lit_table(&report.lit))
    };
    write!(
        out,
        "{}{lit}\nwrote {} ({} images and report.md) in {:.1} s\n",
        crate::demo::scene::report_table(&report.rows),
        a.out.display(),
        report.images,
        t.elapsed().as_secs_f64()
    )
    .and_then(|()| out.flush())
    .map_err(|e| format!("<stdout>: {e}").into())
}
