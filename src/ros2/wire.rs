//! rmw_zenoh's wire format, as its releases 0.2.4 to 0.2.10 (Jazzy), 0.6 (Kilted) and
//! 0.12.0 (Rolling) write it (docs/ros2.md says where each rule is in its source):
//!
//! - data on `DOMAIN/TOPIC/TYPE/HASH`, the topic without its leading `/`;
//! - liveliness tokens under `@ros2_lv` for the node (NN) and each publisher (MP), by
//!   which `ros2 node list` and `ros2 topic list` find them;
//! - on every sample an attachment of 33 bytes: sequence number, source time and the
//!   publisher's id (GID). A subscriber drops a sample without it.

use mechweed_core::config::Distro;

use super::topics::{Offered, Topic};
use super::types::{TRIGGER_DDS, TRIGGER_HASH};

/// The HALT service's entity id: the next after the publishers'.
pub const HALT_ENTITY_ID: u32 = Topic::ALL.len() as u32 + 1;

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

    /// `@ros2_lv/DOMAIN/ZID/NID/EID/KIND/ENCLAVE/NAMESPACE/NODE`: the enclave is rcl's
    /// default, `/` (an empty part would cut the token short where rmw_zenoh reads it).
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
            qos(topic.offered())
        )
    }

    /// The HALT service's name: /NAMESPACE/halt.
    pub fn halt_name(&self) -> String {
        format!("{}/halt", self.namespace.trim_end_matches('/'))
    }

    /// The key a HALT call is a query on: `DOMAIN/NAME/TYPE/HASH`, as a topic's.
    pub fn halt_key(&self) -> String {
        let name = self.halt_name();
        let name = name.trim_start_matches('/');
        format!("{}/{name}/{TRIGGER_DDS}/{TRIGGER_HASH}", self.domain_id)
    }

    /// The service server's token (SS), with rcl's services QoS (reliable, keep last 10).
    pub fn halt_token(&self) -> String {
        let services = Offered {
            depth: 10,
            transient_local: false,
            lifespan_s: None,
        };
        format!(
            "{}/{}/{TRIGGER_DDS}/{TRIGGER_HASH}/{}",
            self.entity(HALT_ENTITY_ID, "SS"),
            mangle(&self.halt_name()),
            qos(services)
        )
    }

    /// The publisher's GID: XXH3-128 of its token, low half first, each little-endian.
    pub fn gid(&self, topic: Topic) -> [u8; 16] {
        xxhash_rust::xxh3::xxh3_128(self.publisher_token(topic).as_bytes()).to_le_bytes()
    }
}

/// The QoS part of a token for a reliable keep-last publisher with no deadline or
/// lease: only what differs from rmw_zenoh's defaults (reliable, volatile, keep last
/// 42, durations without end) is written, `REL:DUR:HIST,DEPTH:DL_S,DL_NS:LIFE_S,
/// LIFE_NS:LIV,LEASE_S,LEASE_NS`. rmw's TRANSIENT_LOCAL is 1; a lifespan's seconds
/// and nanoseconds differ from the endless one's (9223372036 s 854775807 ns) each.
pub fn qos(offered: Offered) -> String {
    let depth = if offered.depth == DEFAULT_DEPTH {
        String::new()
    } else {
        offered.depth.to_string()
    };
    let durability = if offered.transient_local { "1" } else { "" };
    let lifespan = match offered.lifespan_s {
        Some(s) => format!("{s},0"),
        None => ",".to_string(),
    };
    format!(":{durability}:,{depth}:,:{lifespan}:,,")
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

/// The attachment's parts, or why it is not one: what a subscriber reads.
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

#[cfg(test)]
mod tests {
    use super::*;

    fn node() -> Node {
        Node {
            domain_id: 7,
            zid: "8b20917502ee955ac4476e0266340d5c".to_string(),
            namespace: "/farm/mechweed".to_string(),
            distro: Distro::Jazzy,
        }
    }

    #[test]
    fn keys_and_tokens_mangle_the_names_and_carry_type_hash_and_qos() {
        let n = node();
        assert_eq!(
            n.data_key(Topic::Fix),
            "7/farm/mechweed/fix/sensor_msgs::msg::dds_::NavSatFix_/RIHS01_62223ab3fe210a15976021da7afddc9e200dc9ec75231c1b6a557fc598a65404"
        );
        assert_eq!(
            n.data_key(Topic::Tf),
            "7/tf/tf2_msgs::msg::dds_::TFMessage_/RIHS01_e369d0f05a23ae52508854b66f6aa0437f3449d652e8cbf22d5abe85d020f087"
        );
        assert_eq!(
            n.node_token(),
            "@ros2_lv/7/8b20917502ee955ac4476e0266340d5c/0/0/NN/%/%farm%mechweed/ros2_bridge"
        );
        assert_eq!(
            n.publisher_token(Topic::Rosout),
            "@ros2_lv/7/8b20917502ee955ac4476e0266340d5c/0/2/MP/%/%farm%mechweed/ros2_bridge/%rosout/rcl_interfaces::msg::dds_::Log_/RIHS01_e28ce254ca8abc06abf92773b74602cdbf116ed34fbaf294fb9f81da9f318eac/:1:,1000:,:10,0:,,"
        );
        assert_eq!(mangle(""), "%");
        assert_eq!(mangle("/"), "%");
    }

    #[test]
    fn qos_writes_only_what_differs_from_rmw_zenohs_defaults() {
        let volatile = |depth| Offered {
            depth,
            transient_local: false,
            lifespan_s: None,
        };
        // rmw_zenoh's own example: a talker of depth 7.
        assert_eq!(qos(volatile(7)), "::,7:,:,:,,");
        assert_eq!(qos(volatile(DEFAULT_DEPTH)), "::,:,:,:,,");
        // rcl's /rosout (rcl_qos_profile_rosout_default): keep last 1000, reliable,
        // transient local, lifespan 10 s 0 ns; rmw_zenoh writes the lifespan's 0 ns
        // too, as it differs from the endless lifespan's 854775807 ns.
        assert_eq!(qos(Topic::Rosout.offered()), ":1:,1000:,:10,0:,,");
    }

    #[test]
    fn the_gid_is_xxh3_128_of_the_token_low_half_first() {
        // XXH3-128 of nothing is 99aa06d3014798d8 6001c324468d497f (the reference
        // implementation's own check): the low 64 bits come first, little-endian.
        let empty = xxhash_rust::xxh3::xxh3_128(b"").to_le_bytes();
        assert_eq!(
            empty,
            [
                0x7f, 0x49, 0x8d, 0x46, 0x24, 0xc3, 0x01, 0x60, 0xd8, 0x98, 0x47, 0x01, 0xd3, 0x06,
                0xaa, 0x99
            ]
        );
        // The token of /farm/mechweed/odom in domain 7: its XXH3-128 by the reference
        // implementation (the C library, through Python's xxhash 3) is
        // 1dbbd06dc20e4a73 613625af83574365.
        let n = node();
        assert_eq!(n.publisher_token(Topic::Odom).len(), 215);
        let reference = u128::from_str_radix("1dbbd06dc20e4a73613625af83574365", 16).unwrap();
        assert_eq!(n.gid(Topic::Odom), reference.to_le_bytes());
        assert_ne!(n.gid(Topic::Odom), n.gid(Topic::Tf));
    }

    #[test]
    fn the_attachment_is_sequence_time_sixteen_and_the_gid() {
        let gid: [u8; 16] = std::array::from_fn(|i| i as u8 + 0xa0);
        let bytes = attachment(0x0102, -2, &gid);
        let mut expected = vec![0x02, 0x01, 0, 0, 0, 0, 0, 0];
        expected.extend([0xfe, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff]);
        expected.push(0x10);
        expected.extend(gid);
        assert_eq!(bytes.to_vec(), expected);
        assert_eq!(read_attachment(&bytes).unwrap(), (0x0102, -2, gid));
        let why = read_attachment(&bytes[..32]).unwrap_err();
        assert!(why.contains("32 bytes"), "{why}");
    }
}
