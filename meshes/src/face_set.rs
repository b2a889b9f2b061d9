//! A named face set that may hold several face kinds.
//!
//! A physical surface of a hex-dominant mesh has quadrilaterals where hexahedra end and
//! triangles where wedges or tetrahedra do, so a face set keeps one [`CellBlock`] per kind.

use crate::{CellBlock, CellKind};
use serde::{Deserialize, Serialize};

/// Faces of one named surface: one block per face kind, in the order the kinds first appear.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct FaceSet {
    /// One block per face kind (no two blocks of the same kind).
    pub blocks: Vec<CellBlock>,
}

/// One face of a [`FaceSet`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Face<'a> {
    pub kind: CellKind,
    /// Node indices in squeal order.
    pub nodes: &'a [usize],
    /// Element tag as given in the file.
    pub tag: u64,
}

impl FaceSet {
    /// A set holding the single block `block`.
    pub fn from_block(block: CellBlock) -> Self {
        FaceSet {
            blocks: vec![block],
        }
    }

    /// Number of faces over all kinds.
    pub fn len(&self) -> usize {
        self.blocks.iter().map(CellBlock::len).sum()
    }

    pub fn is_empty(&self) -> bool {
        self.blocks.iter().all(CellBlock::is_empty)
    }

    /// The kind of every face when the set has a single kind, else `None` (empty or mixed).
    pub fn kind(&self) -> Option<CellKind> {
        let mut kinds = self.blocks.iter().filter(|b| !b.is_empty()).map(|b| b.kind);
        let first = kinds.next()?;
        kinds.all(|k| k == first).then_some(first)
    }

    /// The kinds present (non-empty blocks), in block order.
    pub fn kinds(&self) -> impl Iterator<Item = CellKind> + '_ {
        self.blocks.iter().filter(|b| !b.is_empty()).map(|b| b.kind)
    }

    /// The block of kind `kind`, if any.
    pub fn block(&self, kind: CellKind) -> Option<&CellBlock> {
        self.blocks.iter().find(|b| b.kind == kind)
    }

    /// The block of kind `kind`, created empty (named `name`) when missing.
    pub fn block_mut(&mut self, kind: CellKind, name: Option<&str>) -> &mut CellBlock {
        let i = match self.blocks.iter().position(|b| b.kind == kind) {
            Some(i) => i,
            None => {
                self.blocks
                    .push(CellBlock::new(name.map(str::to_string), kind));
                self.blocks.len() - 1
            }
        };
        &mut self.blocks[i]
    }

    /// Appends one face of kind `kind` (creating its block when missing).
    pub fn push(&mut self, kind: CellKind, nodes: &[usize], tag: u64) {
        let b = self.block_mut(kind, None);
        b.conn.extend_from_slice(nodes);
        b.tags.push(tag);
    }

    /// Every face, block after block.
    pub fn iter(&self) -> impl Iterator<Item = Face<'_>> + '_ {
        self.blocks.iter().flat_map(|b| {
            (0..b.len()).map(move |i| Face {
                kind: b.kind,
                nodes: b.cell(i),
                tag: b.tags[i],
            })
        })
    }

    /// Every node index of every face (repeated where faces share nodes).
    pub fn node_indices(&self) -> impl Iterator<Item = usize> + '_ {
        self.blocks.iter().flat_map(|b| b.conn.iter().copied())
    }

    /// The nodes of the set, sorted and unique.
    pub fn nodes(&self) -> Vec<usize> {
        let mut v: Vec<usize> = self.node_indices().collect();
        v.sort_unstable();
        v.dedup();
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mixed_kinds_keep_one_block_each() {
        let mut s = FaceSet::default();
        assert_eq!(s.kind(), None);
        assert!(s.is_empty());
        s.push(CellKind::Quad4, &[0, 1, 2, 3], 10);
        assert_eq!(s.kind(), Some(CellKind::Quad4));
        s.push(CellKind::Tri3, &[2, 1, 4], 11);
        s.push(CellKind::Quad4, &[3, 2, 5, 6], 12);
        assert_eq!(s.blocks.len(), 2);
        assert_eq!(s.len(), 3);
        assert_eq!(s.kind(), None);
        assert_eq!(
            s.kinds().collect::<Vec<_>>(),
            [CellKind::Quad4, CellKind::Tri3]
        );
        let tags: Vec<u64> = s.iter().map(|f| f.tag).collect();
        assert_eq!(tags, [10, 12, 11]);
        assert_eq!(s.iter().nth(2).unwrap().nodes, &[2, 1, 4]);
        assert_eq!(s.nodes(), [0, 1, 2, 3, 4, 5, 6]);
        assert_eq!(s.block(CellKind::Tri3).unwrap().len(), 1);
        assert!(s.block(CellKind::Tri6).is_none());
    }
}
