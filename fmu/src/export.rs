//! The packager: an `.fmu` archive from a model's source, its [`Config`] and the
//! library built from this crate.

use std::path::{Path, PathBuf};

use crate::archive::write_zip;
use crate::config::{CONFIG_FILE, Config, SOURCE_FILE};
use crate::description::model_description;
use crate::model::load;
use crate::variables::{self, Variable};

/// The name of this crate's library as cargo builds it on Linux.
pub const LIBRARY_FILE: &str = "libdae_fmu.so";

/// What [`export`] wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct Exported {
    /// The FMU's `modelIdentifier` (its library is `binaries/linux64/<it>.so`).
    pub identifier: String,
    /// The FMU's `guid`.
    pub guid: String,
    /// Its variables, in the order of their value references.
    pub variables: Vec<Variable>,
}

/// The model's name as a C identifier (letters, digits and `_`, not starting with a
/// digit), for the library's file name.
pub fn model_identifier(name: &str) -> String {
    let mut id: String = name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    if !id.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_') {
        id.insert(0, '_');
    }
    id
}

/// FNV-1a over `bytes` from `seed`.
fn fnv1a(seed: u64, bytes: &[u8]) -> u64 {
    bytes.iter().fold(seed, |h, &b| {
        (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// A guid from the source and the configuration: the same export gives the same guid.
fn guid(src: &str, config: &Config) -> String {
    let text = format!(
        "{src}\0{}",
        serde_json::to_string(config).unwrap_or_default()
    );
    let a = fnv1a(0xcbf2_9ce4_8422_2325, text.as_bytes());
    let b = fnv1a(a ^ 0x9e37_79b9_7f4a_7c15, text.as_bytes());
    format!(
        "{{{:08x}-{:04x}-{:04x}-{:04x}-{:012x}}}",
        a >> 32,
        (a >> 16) & 0xffff,
        a & 0xffff,
        b >> 48,
        b & 0xffff_ffff_ffff
    )
}

/// A file of the archive: its path there and its contents.
type File = (String, Vec<u8>);

/// The files of the FMU but its library (path in the archive, contents), and what they
/// declare. The model is compiled and constructed here, so an FMU that is written
/// instantiates.
fn files(src: &str, mut config: Config) -> Result<(Vec<File>, Exported), String> {
    config.check()?;
    config.guid.clear();
    config.guid = guid(src, &config);
    let vars = variables::of(&*load(src, &config)?, config.eps);
    let identifier = model_identifier(&config.model);
    let generation = format!("daec {} (dae-fmu)", env!("CARGO_PKG_VERSION"));
    let description = model_description(&config, &identifier, &vars, &generation);
    let config_json = serde_json::to_string_pretty(&config).map_err(|e| e.to_string())?;
    let files = vec![
        ("modelDescription.xml".to_string(), description.into_bytes()),
        (format!("resources/{SOURCE_FILE}"), src.as_bytes().to_vec()),
        (format!("resources/{CONFIG_FILE}"), config_json.into_bytes()),
    ];
    let exported = Exported {
        identifier,
        guid: config.guid,
        variables: vars,
    };
    Ok((files, exported))
}

/// Writes an FMI 2.0 co-simulation FMU for Linux x86-64 to `out`: the model of `src`
/// named in `config`, run by the library at `library` (this crate's `cdylib`, see
/// [`find_library`]). Every failure is one message.
pub fn export(src: &str, config: Config, library: &Path, out: &Path) -> Result<Exported, String> {
    let (mut files, exported) = self::files(src, config)?;
    let lib = std::fs::read(library).map_err(|e| {
        format!(
            "reading the FMU library `{}`: {e} (build it with `cargo build --release -p dae-fmu`)",
            library.display()
        )
    })?;
    files.insert(
        1,
        (format!("binaries/linux64/{}.so", exported.identifier), lib),
    );
    let mut file = std::io::BufWriter::new(
        std::fs::File::create(out).map_err(|e| format!("creating `{}`: {e}", out.display()))?,
    );
    write_zip(&mut file, &files)
        .and_then(|()| std::io::Write::flush(&mut file))
        .map_err(|e| format!("writing `{}`: {e}", out.display()))?;
    Ok(exported)
}

/// Writes the FMU unpacked into `dir` without its library (`modelDescription.xml` and
/// `resources/`), as an importer unpacks it: for running the FMU in the same process
/// through [`abi`](crate::abi), whose `fmi2Instantiate` takes
/// `file://<dir>/resources`.
pub fn unpack(src: &str, config: Config, dir: &Path) -> Result<Exported, String> {
    let (files, exported) = self::files(src, config)?;
    for (name, data) in files {
        let path = dir.join(name);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent)
                .map_err(|e| format!("creating `{}`: {e}", parent.display()))?;
        }
        std::fs::write(&path, data).map_err(|e| format!("writing `{}`: {e}", path.display()))?;
    }
    Ok(exported)
}

/// Where this crate's library is: `$DAE_FMU_LIBRARY` if set, else [`LIBRARY_FILE`]
/// beside the running program or one folder up (cargo puts `daec` in `target/release`
/// and test programs in `target/release/deps`, the library in `target/release`).
pub fn find_library() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("DAE_FMU_LIBRARY") {
        return Some(PathBuf::from(p));
    }
    let exe = std::env::current_exe().ok()?;
    let dir = exe.parent()?;
    [dir.join(LIBRARY_FILE), dir.parent()?.join(LIBRARY_FILE)]
        .into_iter()
        .find(|p| p.is_file())
}

#[cfg(test)]
mod tests {
    use super::{guid, model_identifier};
    use crate::config::Config;

    #[test]
    fn identifiers_are_c_names() {
        assert_eq!(model_identifier("DoublePendulum3D"), "DoublePendulum3D");
        assert_eq!(model_identifier("3-bar"), "_3_bar");
    }

    #[test]
    fn the_guid_follows_the_source_and_the_config() {
        let c = Config::new("M", 1e-3, 1.0);
        let g = guid("model M {}", &c);
        assert_eq!(g, guid("model M {}", &c));
        assert_ne!(g, guid("model M { }", &c));
        assert_ne!(g, guid("model M {}", &Config::new("M", 1e-2, 1.0)));
        assert_eq!(g.len(), 38);
    }
}
