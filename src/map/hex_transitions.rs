//! placeholder
use hexx::Hex;
/// One hexagon of a learned map, as exported.
#[derive(Debug, Clone, PartialEq)]
pub struct HexCell {
    /// Axial coordinates.
    pub hex: Hex,
    /// Crossings of each edge (edge order of [`crate::geometry::HexGrid`]: 0 = E, 1 = NE,
    /// 2 = NW, 3 = W, 4 = SW, 5 = SE), counted in both directions.
    pub counts: [u32; 6],
}
/// A read-only copy of a map for export.
#[derive(Debug, Clone, PartialEq)]
pub struct HexMapSnapshot {
    /// Hexagon circumradius, metres.
    pub radius: f64,
    /// Dirichlet prior per edge.
    pub alpha: f64,
    /// Visited hexagons, sorted by (q, r).
    pub cells: Vec<HexCell>,
}
/// placeholder
pub struct HexTransitionMap;
