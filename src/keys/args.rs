//! The command line's way to name this program's identity: `--keys DIR --as NAME`, or
//! the three files `--ca --cert --key`. Without them a tool speaks plain TCP.

use std::path::PathBuf;

use crate::config::TlsFiles;

#[derive(clap::Args, Clone, Debug, Default)]
pub struct IdentityArgs {
    /// The cluster's keys folder (mechweed keys new DIR); with --as, this program's
    /// identity in it: TLS, with DIR/ca.pem, DIR/NAME.pem and DIR/NAME.key.
    #[arg(long = "keys", id = "keys_dir", value_name = "DIR", global = true, requires = "identity_name", conflicts_with_all = ["tls_ca", "tls_cert", "tls_key"])]
    pub keys: Option<PathBuf>,
    /// This program's identity in --keys DIR, e.g. operator or laptop-2.
    #[arg(
        long = "as",
        id = "identity_name",
        value_name = "NAME",
        global = true,
        requires = "keys_dir"
    )]
    pub name: Option<String>,
    /// The cluster authority's certificate (with --cert and --key): TLS.
    #[arg(long = "ca", id = "tls_ca", value_name = "FILE", global = true, requires_all = ["tls_cert", "tls_key"])]
    pub ca: Option<PathBuf>,
    /// This program's certificate (with --ca and --key).
    #[arg(long = "cert", id = "tls_cert", value_name = "FILE", global = true, requires_all = ["tls_ca", "tls_key"])]
    pub cert: Option<PathBuf>,
    /// This program's private key (with --ca and --cert).
    #[arg(long = "key", id = "tls_key", value_name = "FILE", global = true, requires_all = ["tls_ca", "tls_cert"])]
    pub key: Option<PathBuf>,
}

impl IdentityArgs {
    /// The identity's files, or None for plain TCP.
    pub fn files(&self) -> Option<TlsFiles> {
        match (&self.keys, &self.name, &self.ca, &self.cert, &self.key) {
            (Some(dir), Some(name), ..) => Some(TlsFiles::in_folder(dir, name)),
            (_, _, Some(ca), Some(cert), Some(key)) => Some(TlsFiles {
                ca: ca.clone(),
                cert: cert.clone(),
                key: key.clone(),
            }),
            _ => None,
        }
    }
}
