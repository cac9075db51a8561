//! `mechweed keys ...`: make the cluster's authority and identities, add one, revoke one.

use std::path::PathBuf;

use clap::Subcommand;

use super::{Role, add_identity, new_cluster, revoke};

#[derive(Subcommand)]
pub enum KeysCommand {
    /// Make the cluster's authority (DIR/ca.pem, DIR/ca.key), one key and certificate
    /// per role (DIR/ROLE.pem, DIR/ROLE.key) and the roster of who is who (DIR/roles.ini).
    New {
        dir: PathBuf,
        /// The robot's name on the bus ([bus] robot): the access rules cover its keys.
        #[arg(long, value_name = "NAME", default_value = "mechweed")]
        robot: String,
    },
    /// Make one more identity (DIR/NAME.pem, DIR/NAME.key), e.g. a second laptop:
    /// `keys add keys operator laptop-2`. A launcher's name is its machine's name.
    Add {
        dir: PathBuf,
        /// robot, camera, operator, viewer, recorder, master or launcher.
        #[arg(value_parser = Role::parse)]
        role: Role,
        name: String,
    },
    /// Take an identity's rights away (a lost laptop): it leaves the roster for good.
    /// Copy DIR/roles.ini to every computer of the cluster afterwards.
    Revoke { dir: PathBuf, name: String },
}

pub fn run(command: KeysCommand) -> Result<String, String> {
    match command {
        KeysCommand::New { dir, robot } => {
            let made = new_cluster(&dir, &robot)?;
            Ok(format!(
                "made in {}: {}\n\
                 private keys (*.key) are readable by their owner only. Give each computer ca.pem,\n\
                 roles.ini and the .pem and .key of the identities it runs; keep ca.key off the\n\
                 field network (it is needed only to make more)",
                dir.display(),
                made.join(", ")
            ))
        }
        KeysCommand::Add { dir, role, name } => {
            let made = add_identity(&dir, role, &name)?;
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
                super::roster::path_in(&dir).display()
            ))
        }
    }
}
