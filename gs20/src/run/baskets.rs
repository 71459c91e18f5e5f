// SPDX-License-Identifier: MIT OR Apache-2.0
//! The baskets file: what the module's configuration tool stores in its flash, and Add
//! Basket (0x01) selects by ID (reference §1.7).
//!
//! ```toml
//! # Basket 1: 8 bytes each way at slot 1, 4 bytes of inputs at slot 2.
//! [[basket]]
//! id = 1
//! items = [{ item = 3008, slot = 1 }, { item = 1004, slot = 2 }]
//! ```
//!
//! The item IDs are checked here; the slots, and whether the items fit together, when the
//! host selects the basket (error bit 1 then, as the module answers a basket with invalid
//! data).

use procimg_gs20::link::{Baskets, ItemSlot};
use procimg_gs20::messages::{ItemId, ItemIdError};
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// Why the baskets file cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum BasketsError {
    /// It cannot be read.
    #[error("cannot read the baskets file {path}: {cause}")]
    Read {
        /// The file.
        path: PathBuf,
        /// Why.
        cause: std::io::Error,
    },
    /// It is no baskets file.
    #[error(
        "the baskets file {path} is not valid: {cause}; write [[basket]] tables with an id \
         and items = [{{ item = 3008, slot = 1 }}, ...]"
    )]
    Parse {
        /// The file.
        path: PathBuf,
        /// Why.
        cause: toml::de::Error,
    },
    /// An item ID is not in the catalogue.
    #[error("the baskets file {path}, basket {basket}: {cause}")]
    Item {
        /// The file.
        path: PathBuf,
        /// The basket.
        basket: u16,
        /// Why.
        cause: ItemIdError,
    },
    /// Two baskets have one ID.
    #[error("the baskets file {path} has basket {basket} twice; give each basket its own id")]
    Duplicate {
        /// The file.
        path: PathBuf,
        /// The basket.
        basket: u16,
    },
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    #[serde(default)]
    basket: Vec<Basket>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Basket {
    id: u16,
    items: Vec<Item>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Item {
    item: u16,
    slot: u16,
}

/// Reads the baskets file at `path`.
pub fn load(path: &Path) -> Result<Baskets, BasketsError> {
    let text = std::fs::read_to_string(path).map_err(|cause| BasketsError::Read {
        path: path.to_owned(),
        cause,
    })?;
    parse(&text, path)
}

/// Parses the text of the baskets file `path`.
fn parse(text: &str, path: &Path) -> Result<Baskets, BasketsError> {
    let file: File = toml::from_str(text).map_err(|cause| BasketsError::Parse {
        path: path.to_owned(),
        cause,
    })?;
    let mut baskets = Baskets::new();
    for b in file.basket {
        let items = b
            .items
            .iter()
            .map(|i| {
                ItemId::from_u16(i.item)
                    .map(|item| ItemSlot { item, slot: i.slot })
                    .map_err(|cause| BasketsError::Item {
                        path: path.to_owned(),
                        basket: b.id,
                        cause,
                    })
            })
            .collect::<Result<Vec<_>, _>>()?;
        if baskets.insert(b.id, items).is_some() {
            return Err(BasketsError::Duplicate {
                path: path.to_owned(),
                basket: b.id,
            });
        }
    }
    Ok(baskets)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn baskets_by_id_with_their_items_in_order() {
        let text = "[[basket]]\nid = 1\nitems = [{ item = 3008, slot = 1 }, { item = 1004, slot = 2 }]\n\
                    [[basket]]\nid = 7\nitems = []\n";
        let b = parse(text, Path::new("b.toml")).unwrap();
        assert_eq!(b.len(), 2);
        assert_eq!(b[&1][1].item.to_u16(), 1004);
        assert_eq!(b[&1][1].slot, 2);
        assert!(
            b[&7].is_empty(),
            "refused when selected, as the module does"
        );
    }

    #[test]
    fn bad_files_are_named() {
        let e = parse(
            "[[basket]]\nid = 1\nitems = [{ item = 4008, slot = 1 }]\n",
            Path::new("b.toml"),
        )
        .unwrap_err();
        assert!(
            e.to_string().contains("basket 1") && e.to_string().contains("4008"),
            "{e}"
        );
        let e = parse(
            "[[basket]]\nid = 1\nitems = []\n[[basket]]\nid = 1\nitems = []\n",
            Path::new("b.toml"),
        )
        .unwrap_err();
        assert!(matches!(e, BasketsError::Duplicate { basket: 1, .. }));
        let e = parse("[[basket]]\nid = 1\n", Path::new("b.toml")).unwrap_err();
        assert!(e.to_string().contains("b.toml"), "{e}");
    }
}
