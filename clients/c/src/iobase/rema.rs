// SPDX-License-Identifier: MIT OR Apache-2.0
//! The controller interface's retentive data ("REMA"), as PN Driver hands it to its program
//! (`PNIO_CBE_REMA_READ_CONF`) and takes it back at the next start (`SERV_CP_startup`'s
//! `pRemaData`): the station's NameOfStation and IP suite that a program or DCP set to be
//! kept. The program stores the text and never looks inside; its format is procimg's own, a
//! small XML document:
//!
//! ```xml
//! <?xml version="1.0" encoding="UTF-8"?>
//! <RemanentData xmlns="urn:procimg:rema:1">
//!   <NameOfStation>plc-line-1</NameOfStation>
//!   <IPSuite Address="192.168.0.1" SubnetMask="255.255.255.0" DefaultRouter="0.0.0.0"/>
//! </RemanentData>
//! ```

use std::net::Ipv4Addr;

/// The namespace of the document.
const NAMESPACE: &str = "urn:procimg:rema:1";

/// The station's remanent name and IP suite.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct RemanentData {
    /// NameOfStation.
    pub name: String,
    /// Address, subnet mask, default router.
    pub ip_suite: [Ipv4Addr; 3],
}

impl RemanentData {
    /// The document.
    pub(crate) fn to_xml(&self) -> String {
        let [ip, mask, router] = self.ip_suite;
        format!(
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<RemanentData xmlns=\"{NAMESPACE}\">\n  \
             <NameOfStation>{}</NameOfStation>\n  <IPSuite Address=\"{ip}\" \
             SubnetMask=\"{mask}\" DefaultRouter=\"{router}\"/>\n</RemanentData>\n",
            escape(&self.name)
        )
    }

    /// Reads a document [`to_xml`](Self::to_xml) wrote; why not, in words.
    pub(crate) fn parse(text: &str) -> Result<RemanentData, String> {
        let doc = roxmltree::Document::parse(text).map_err(|e| format!("not XML: {e}"))?;
        let root = doc.root_element();
        if root.tag_name().name() != "RemanentData"
            || root.tag_name().namespace() != Some(NAMESPACE)
        {
            return Err(format!(
                "the root element is not procimg's RemanentData ({NAMESPACE}): retentive data \
                 of another stack"
            ));
        }
        let child = |name: &str| {
            root.children()
                .find(|n| n.is_element() && n.tag_name().name() == name)
                .ok_or_else(|| format!("no {name} element"))
        };
        let name = child("NameOfStation")?
            .text()
            .unwrap_or_default()
            .to_owned();
        let suite = child("IPSuite")?;
        let address = |attr: &str| -> Result<Ipv4Addr, String> {
            let v = suite
                .attribute(attr)
                .ok_or_else(|| format!("IPSuite has no {attr}"))?;
            v.parse()
                .map_err(|_| format!("IPSuite {attr} {v:?} is not an IPv4 address"))
        };
        Ok(RemanentData {
            name,
            ip_suite: [
                address("Address")?,
                address("SubnetMask")?,
                address("DefaultRouter")?,
            ],
        })
    }
}

/// `s` as XML character data.
fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_document_reads_back() {
        let d = RemanentData {
            name: "plc-line-1".into(),
            ip_suite: [
                Ipv4Addr::new(192, 168, 0, 1),
                Ipv4Addr::new(255, 255, 255, 0),
                Ipv4Addr::UNSPECIFIED,
            ],
        };
        assert_eq!(RemanentData::parse(&d.to_xml()), Ok(d));
    }

    #[test]
    fn another_stacks_data_is_refused() {
        assert!(RemanentData::parse("<PNDriverRema/>").is_err());
        assert!(RemanentData::parse("not xml").is_err());
        let no_suite = format!(
            "<RemanentData xmlns=\"{NAMESPACE}\"><NameOfStation>a</NameOfStation></RemanentData>"
        );
        assert!(
            RemanentData::parse(&no_suite)
                .unwrap_err()
                .contains("IPSuite")
        );
    }
}
