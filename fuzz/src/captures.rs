// SPDX-License-Identifier: MIT OR Apache-2.0
//! The captured frames the seeds are cut from: `profinet/tests/fixtures/captures` (real frames
//! between an S7-1515 and the p-net sample device, the test data of the `pnio` crate 0.1.0,
//! MIT OR Apache-2.0; see the README there), one frame per `.hex` file, plus every Ethernet
//! frame of any `.pcap` or `.pcapng` file put beside them.
//!
//! The cutters return the part of a frame each target parses: the PROFINET PDU behind the
//! EtherType, the UDP payload (an RPC PDU), the PNIO blocks behind the RPC and NDR headers.

use pcap_file::DataLink;
use pcap_file::pcap::PcapReader;
use pcap_file::pcapng::{Block, PcapNgReader};
use procimg_profinet::wire::ethernet::{self, ETHERTYPE_PROFINET};
use procimg_profinet::wire::rpc;
use std::fs::File;
use std::path::{Path, PathBuf};

/// One captured frame.
#[derive(Clone, Debug)]
pub struct Captured {
    /// Where it came from: the file's path below the captures folder without its extension,
    /// with the packet number for pcap files (`cm/connect_req`, `x/run.pcap-3`).
    pub name: String,
    /// The Ethernet frame, header first, without FCS.
    pub frame: Vec<u8>,
}

/// The captures folder of the repository.
pub fn default_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../profinet/tests/fixtures/captures")
}

/// Every frame below `dir`, in path order.
pub fn load(dir: &Path) -> std::io::Result<Vec<Captured>> {
    let mut files = Vec::new();
    walk(dir, &mut files)?;
    files.sort();
    let mut out = Vec::new();
    for path in files {
        let rel = path.strip_prefix(dir).unwrap_or(&path);
        let stem = rel.with_extension("").to_string_lossy().replace('\\', "/");
        match path.extension().and_then(|e| e.to_str()) {
            Some("hex") => out.push(Captured {
                name: stem,
                frame: parse_hex(&std::fs::read_to_string(&path)?).map_err(|e| {
                    std::io::Error::new(
                        std::io::ErrorKind::InvalidData,
                        format!("{}: {e}", path.display()),
                    )
                })?,
            }),
            Some(ext @ ("pcap" | "pcapng")) => {
                for (i, frame) in read_pcap(&path, ext == "pcapng")?.into_iter().enumerate() {
                    out.push(Captured {
                        name: format!("{stem}.{ext}-{i}"),
                        frame,
                    });
                }
            }
            _ => {}
        }
    }
    Ok(out)
}

fn walk(dir: &Path, files: &mut Vec<PathBuf>) -> std::io::Result<()> {
    for entry in std::fs::read_dir(dir)? {
        let path = entry?.path();
        if path.is_dir() {
            walk(&path, files)?;
        } else {
            files.push(path);
        }
    }
    Ok(())
}

/// The bytes of a `.hex` capture: `#` lines are comments, the rest hex digits in pairs with
/// any whitespace between them.
pub fn parse_hex(text: &str) -> Result<Vec<u8>, String> {
    let digits: String = text
        .lines()
        .filter(|l| !l.trim_start().starts_with('#'))
        .flat_map(str::split_whitespace)
        .collect();
    if !digits.len().is_multiple_of(2) {
        return Err("an odd number of hex digits".into());
    }
    (0..digits.len())
        .step_by(2)
        .map(|i| {
            u8::from_str_radix(&digits[i..i + 2], 16)
                .map_err(|_| format!("{:?} is not a hex byte", &digits[i..i + 2]))
        })
        .collect()
}

/// The Ethernet frames of a pcap or pcapng file (other link types are skipped).
fn read_pcap(path: &Path, ng: bool) -> std::io::Result<Vec<Vec<u8>>> {
    let bad = |e: pcap_file::PcapError| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!("{}: {e}", path.display()),
        )
    };
    let file = File::open(path)?;
    let mut frames = Vec::new();
    if ng {
        let mut r = PcapNgReader::new(file).map_err(bad)?;
        // The link type of each interface, in the order they were described.
        let mut links = Vec::new();
        while let Some(block) = r.next_block() {
            let ethernet = |i: u32| links.get(i as usize) == Some(&DataLink::ETHERNET);
            match block.map_err(bad)? {
                Block::InterfaceDescription(i) => links.push(i.linktype),
                Block::EnhancedPacket(p) if ethernet(p.interface_id) => {
                    frames.push(p.data.into_owned())
                }
                // A simple packet belongs to the first interface.
                Block::SimplePacket(p) if ethernet(0) => frames.push(p.data.into_owned()),
                _ => {}
            }
        }
    } else {
        let mut r = PcapReader::new(file).map_err(bad)?;
        if r.header().datalink != DataLink::ETHERNET {
            return Ok(frames);
        }
        while let Some(p) = r.next_packet() {
            frames.push(p.map_err(bad)?.data.into_owned());
        }
    }
    Ok(frames)
}

/// The PROFINET PDU of a frame (from the FrameID on, Ethernet padding included), if its
/// EtherType is 0x8892.
pub fn profinet_pdu(frame: &[u8]) -> Option<&[u8]> {
    let eth = ethernet::Frame::new_checked(frame).ok()?;
    (eth.ethertype() == ETHERTYPE_PROFINET).then(|| eth.payload())
}

/// The UDP payload of an IPv4 frame (tagged or not), as long as the UDP header says.
pub fn udp_payload(frame: &[u8]) -> Option<&[u8]> {
    let eth = ethernet::Frame::new_checked(frame).ok()?;
    if eth.ethertype() != 0x0800 {
        return None;
    }
    let ip = eth.payload();
    let ihl = usize::from(ip.first()? & 0x0f) * 4;
    if ip.first()? >> 4 != 4 || ihl < 20 || *ip.get(9)? != 17 {
        return None;
    }
    let udp = ip.get(ihl..)?;
    let len = usize::from(u16::from_be_bytes([*udp.get(4)?, *udp.get(5)?]));
    udp.get(8..len)
}

/// The PNIO blocks of a frame carrying an RPC request or response: the bytes after the
/// 80-byte RPC header and the 20-byte NDR header.
pub fn rpc_blocks(frame: &[u8]) -> Option<&[u8]> {
    rpc::Pdu::parse(udp_payload(frame)?).ok().map(|p| p.blocks)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_capture_loads_and_cuts() {
        let all = load(&default_dir()).unwrap();
        assert!(all.len() >= 30, "{} captures", all.len());
        let connect = all.iter().find(|c| c.name == "cm/connect_req").unwrap();
        let blocks = rpc_blocks(&connect.frame).unwrap();
        // The ARBlockReq comes first.
        assert_eq!(&blocks[..2], &[0x01, 0x01]);
        let dcp = all.iter().find(|c| c.name == "cm/ident_ok_pnet").unwrap();
        assert_eq!(&profinet_pdu(&dcp.frame).unwrap()[..2], &[0xfe, 0xff]);
    }

    #[test]
    fn hex_comments_and_errors() {
        assert_eq!(parse_hex("# x\n01 02\n0a").unwrap(), vec![1, 2, 10]);
        assert!(parse_hex("012").is_err());
        assert!(parse_hex("zz").is_err());
    }
}
