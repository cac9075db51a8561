//! rmw_zenoh's wire format, as its releases 0.2.4 to 0.2.10 (Jazzy), 0.6 (Kilted) and
//! 0.12.0 (Rolling) write it (docs/ros2.md says where each rule is in its source):
//!
//! - data on `DOMAIN/TOPIC/TYPE/HASH`, the topic without its leading `/`;
//! - liveliness tokens under `@ros2_lv` for the node (NN) and each publisher (MP), by
//!   which `ros2 node list` and `ros2 topic list` find them;
//! - on every sample an attachment of 33 bytes: sequence number, source time and the
//!   publisher's id (GID). A subscriber drops a sample without it.

use mechweed_core::config::Distro;

use super::topics::Topic;

/// The node's name; its namespace is `[ros2] namespace`.
pub const NODE_NAME: &str = "ros2_bridge";
/// rmw_zenoh's default history depth: a token leaves out a depth equal to it.
const DEFAULT_DEPTH: u32 = 42;

/// Every `/` of a name as `%`, and an empty part as `%`: a token's parts are
/// separated by `/`.
pub fn mangle(name: &str) -> String {
    if name.is_empty() {
        "%".to_string()
    } else {
        name.replace('/', "%")
    }
}

/// Who the tokens say publishes: the domain, the Zenoh session's id and the node.
#[derive(Debug, Clone)]
pub struct Node {
    pub domain_id: u32,
    /// The session's id as Zenoh writes it (hex).
    pub zid: String,
    pub namespace: String,
    pub distro: Distro,
}

/// The node takes id 0, its publishers 1, 2, ... in the order of `Topic::ALL`: one
/// counter for the node and its entities, as rmw_zenoh keeps it.
pub fn entity_id(topic: Topic) -> u32 {
    Topic::ALL.iter().position(|t| *t == topic).unwrap_or(0) as u32 + 1
}

impl Node {
    /// The key a topic's samples are put on.
    pub fn data_key(&self, topic: Topic) -> String {
        let t = topic.msg_type();
        format!(
            "{}/{}/{}/{}",
            self.domain_id,
            topic.name(&self.namespace).trim_start_matches('/'),
            t.dds_name(),
            t.hash(self.distro)
        )
    }

    /// `@ros2_lv/DOMAIN/ZID/NID/EID/KIND/ENCLAVE/NAMESPACE/NODE`: the enclave is empty.
    fn entity(&self, eid: u32, kind: &str) -> String {
        format!(
            "@ros2_lv/{}/{}/0/{eid}/{kind}/%/{}/{NODE_NAME}",
            self.domain_id,
            self.zid,
            mangle(&self.namespace)
        )
    }

    /// The node's token.
    pub fn node_token(&self) -> String {
        self.entity(0, "NN")
    }

    /// A publisher's token: the node's, then the topic, type, hash and QoS.
    pub fn publisher_token(&self, topic: Topic) -> String {
        let t = topic.msg_type();
        format!(
            "{}/{}/{}/{}/{}",
            self.entity(entity_id(topic), "MP"),
            mangle(&topic.name(&self.namespace)),
            t.dds_name(),
            t.hash(self.distro),
            qos(topic.depth())
        )
    }

    /// The publisher's GID: XXH3-128 of its token, low half first, each little-endian.
    pub fn gid(&self, topic: Topic) -> [u8; 16] {
        twox_hash::xxh3::hash128(self.publisher_token(topic).as_bytes()).to_le_bytes()
    }
}

/// The QoS part of a token for a reliable, volatile, keep-last publisher of `depth`
/// with no deadline, lifespan or lease: only what differs from rmw_zenoh's defaults
/// is written, `REL:DUR:HIST,DEPTH:DEADLINE:LIFESPAN:LIVELINESS`.
pub fn qos(depth: u32) -> String {
    let depth = if depth == DEFAULT_DEPTH {
        String::new()
    } else {
        depth.to_string()
    };
    format!("::,{depth}:,:,:,,")
}

/// The attachment of one sample: sequence number (from 1), source time in ns since
/// 1970 (both i64 little-endian), the GID's length 16 as one byte, and the GID.
pub fn attachment(sequence: i64, source_time_ns: i64, gid: &[u8; 16]) -> [u8; 33] {
    let mut bytes = [0u8; 33];
    bytes[..8].copy_from_slice(&sequence.to_le_bytes());
    bytes[8..16].copy_from_slice(&source_time_ns.to_le_bytes());
    bytes[16] = 16;
    bytes[17..].copy_from_slice(gid);
    bytes
}

/// The attachment's parts, or why it is not one (tests and `mechweed ros2 --check`).
pub fn read_attachment(bytes: &[u8]) -> Result<(i64, i64, [u8; 16]), String> {
    if bytes.len() != 33 || bytes[16] != 16 {
        return Err(format!(
            "an attachment of {} bytes, not rmw_zenoh's 33 (sequence, time, 16, id)",
            bytes.len()
        ));
    }
    let i64_at = |at: usize| {
        let mut b = [0u8; 8];
        b.copy_from_slice(&bytes[at..at + 8]);
        i64::from_le_bytes(b)
    };
    let mut gid = [0u8; 16];
    gid.copy_from_slice(&bytes[17..]);
    Ok((i64_at(0), i64_at(8), gid))
}
