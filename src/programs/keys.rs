//! `mechweed keys ...`: make the cluster's authority and identities, add one, revoke one.
//! And the options by which every networked program names its own identity
//! (`--keys DIR --as NAME`, or the three files `--ca --cert --key`): without them a
//! tool speaks plain TCP.

use std::path::PathBuf;

use clap::Subcommand;

use crate::bus::keys::{Role, add_identity, new_cluster, revoke};
use crate::config::TlsFiles;

#[derive(Subcommand)]
pub enum KeysCommand {
    /// Make the cluster's authority (DIR/ca.pem, DIR/ca.key), one key and certificate
    /// per role (DIR/ROLE.pem, DIR/ROLE.key) and the roster of who is who (DIR/roles.ini).
    New {
        dir: PathBuf,
        /// The robot's name on the bus ([bus] robot): the access rules cover its keys.
        #[arg(long, value_name = "NAME", default_value = "mechweed")]
        robot: String,
        #[command(flatten)]
        hosts: HostArgs,
    },
    /// Make one more identity (DIR/NAME.pem, DIR/NAME.key), e.g. a second laptop:
    /// `keys add keys operator laptop-2`. A launcher's name is its machine's name.
    Add {
        dir: PathBuf,
        /// robot, camera, operator, viewer, recorder, master or launcher.
        #[arg(value_parser = Role::parse)]
        role: Role,
        name: String,
        #[command(flatten)]
        hosts: HostArgs,
    },
    /// Take an identity's rights away (a lost laptop): it leaves the roster for good.
    /// Copy DIR/roles.ini to every computer of the cluster afterwards.
    Revoke { dir: PathBuf, name: String },
}

/// The host names and addresses a certificate names besides its identity: those a
/// standard TLS client dials the robot (or the master) by, which it checks.
#[derive(clap::Args)]
pub struct HostArgs {
    /// A host name this identity is reached by, e.g. robot-pc (repeatable; for keys
    /// new, the robot's).
    #[arg(long = "host", value_name = "NAME")]
    host: Vec<String>,
    /// An address this identity is reached at, e.g. 192.168.1.10 (repeatable).
    #[arg(long = "ip", value_name = "ADDRESS")]
    ip: Vec<std::net::IpAddr>,
}

impl HostArgs {
    fn names(&self) -> Vec<String> {
        let ips = self.ip.iter().map(ToString::to_string);
        self.host.iter().cloned().chain(ips).collect()
    }
}

pub fn run(command: KeysCommand) -> Result<String, String> {
    match command {
        KeysCommand::New { dir, robot, hosts } => {
            let made = new_cluster(&dir, &robot, &hosts.names())?;
            Ok(format!(
                "made in {}: {}\n\
                 private keys (*.key) are readable by their owner only. Give each computer ca.pem,\n\
                 roles.ini and the .pem and .key of the identities it runs; keep ca.key off the\n\
                 field network (it is needed only to make more)",
                dir.display(),
                made.join(", ")
            ))
        }
        KeysCommand::Add {
            dir,
            role,
            name,
            hosts,
        } => {
            let made = add_identity(&dir, role, &name, &hosts.names())?;
            Ok(format!(
                "made in {}: {} ({role}); roles.ini now names it: copy it to every computer of the cluster",
                dir.display(),
                made.join(", ")
            ))
        }
        KeysCommand::Revoke { dir, name } => {
            let role = revoke(&dir, &name)?;
            Ok(format!(
                "{name} ({role}) revoked in {}: copy it to every computer of the cluster and restart their programs; until then they still know the name",
                crate::bus::keys::roster::path_in(&dir).display()
            ))
        }
    }
}

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
