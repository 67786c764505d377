//! `daec fmu FILE --eps E -o MODEL.fmu`: an FMI 2.0 co-simulation FMU of a model, run by
//! DBSMC with the online design of `daec run` (`dae_fmu`).

use std::path::PathBuf;

use crate::Reported;
use crate::run::OnOff;

/// Arguments of `daec fmu`.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// The `.dae` file.
    file: PathBuf,
    /// The model to export when the file holds several.
    #[arg(long)]
    model: Option<String>,
    /// A size or a scalar parameter, fixed at export (`--set N=10`): sizes fix the
    /// number of variables; a scalar parameter's value becomes its start value.
    #[arg(long = "set", value_name = "NAME=VALUE", value_parser = crate::family::parse_assignment)]
    set: Vec<(String, f64)>,
    /// The layer half-width of every constraint: the start value of the FMU's parameter
    /// `eps`.
    #[arg(long)]
    eps: f64,
    /// The frame of the online design (as `daec run --frame`).
    #[arg(long, default_value_t = 1.0 / 60.0)]
    frame: f64,
    /// Search for mu during the run (as `daec run --mu-search`) [default: the design's
    /// choice].
    #[arg(long, value_enum)]
    mu_search: Option<OnOff>,
    /// The default experiment's stop time (seconds from 0).
    #[arg(long, default_value_t = 10.0)]
    stop_time: f64,
    /// The default experiment's communication step [default: --frame].
    #[arg(long)]
    step_size: Option<f64>,
    /// The FMU library (`libdae_fmu.so`) [default: $DAE_FMU_LIBRARY, or beside daec].
    #[arg(long)]
    library: Option<PathBuf>,
    /// The `.fmu` file to write.
    #[arg(short, long)]
    output: PathBuf,
}

pub(crate) fn run(args: &Args) -> Result<(), Reported> {
    // The checks and messages of `daec run`: the model, its sizes and parameters.
    let model = crate::family::runnable(&args.file, args.model.as_deref(), &args.set, None)?;
    let src = std::fs::read_to_string(&args.file).map_err(|e| {
        error!("cannot read `{}`: {e}", args.file.display());
        Reported
    })?;
    let Some(library) = args.library.clone().or_else(dae_fmu::find_library) else {
        error!(
            "no FMU library: `{}` is neither in $DAE_FMU_LIBRARY nor beside daec",
            dae_fmu::LIBRARY_FILE
        );
        hint!("build it with `cargo build --release -p dae-fmu`, or give --library PATH");
        return Err(Reported);
    };
    let mut config = dae_fmu::Config::new(model.name(), args.eps, args.stop_time);
    config.sets = args.set.clone();
    config.frame = args.frame;
    config.step_size = args.step_size.unwrap_or(args.frame);
    config.mu_search = args.mu_search.map(|o| o == OnOff::On);
    match dae_fmu::export(&src, config, &library, &args.output) {
        Ok(e) => {
            println!(
                "{}: FMI 2.0 co-simulation, model identifier {}, {} variables, guid {}",
                args.output.display(),
                e.identifier,
                e.variables.len(),
                e.guid
            );
            Ok(())
        }
        Err(e) => {
            error!("daec fmu: {e}");
            Err(Reported)
        }
    }
}
