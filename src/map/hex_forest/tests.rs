use super::*;
use crate::map::hex_tree::HexTree;
use crate::random::stream;
use rand::RngExt;
use std::collections::BTreeMap;

/// The non-default records of a map, by hexagon.
fn contents(f: impl FnOnce(&mut dyn FnMut(Hex, &u32))) -> BTreeMap<(i32, i32), u32> {
    let mut out = BTreeMap::new();
    f(&mut |h, &v| {
        if v != 0 {
            out.insert((h.x, h.y), v);
        }
    });
    out
}

/// Maps written, resampled and collected at random hold exactly what reference-counted
/// copy-on-write trees ([`HexTree`]) given the same writes hold.
#[test]
fn maps_match_copy_on_write_trees_through_resampling_and_collection() {
    let n = 40;
    let mut forest: HexForest<u32> = HexForest::new();
    let mut maps: Vec<ForestMap<u32>> = vec![ForestMap::default(); n];
    let mut trees: Vec<HexTree<u32>> = vec![HexTree::new(); n];
    let mut children = Vec::new();
    for round in 0..60u64 {
        let mut rng = stream(7, round, 0);
        for (i, (m, t)) in maps.iter_mut().zip(&mut trees).enumerate() {
            // A walk near the origin, with now and then a write far away (the tree grows).
            for _ in 0..rng.random_range(0..6) {
                let h = if rng.random::<f64>() < 0.05 {
                    Hex::new(rng.random_range(-90_000..90_000), rng.random_range(-9..9))
                } else {
                    Hex::new(
                        rng.random_range(-30..30) + i32::try_from(i).unwrap(),
                        rng.random_range(-20..20),
                    )
                };
                let (leaf, slot) = locate(h);
                forest.leaf_mut(m, leaf)[slot] += 1 + round as u32;
                *t.get_mut(h) += 1 + round as u32;
            }
        }
        // Resample: some particles die, others have several children.
        let parents: Vec<usize> = (0..n).map(|_| rng.random_range(0..n / 2) * 2 % n).collect();
        let mut next = vec![ForestMap::default(); n];
        let new = &mut next[..];
        forest.inherit(&mut maps, |m| m, &parents, &mut children, (new, |m| m));
        maps = next;
        trees = parents.iter().map(|&j| trees[j].clone()).collect();
        if round % 7 == 6 {
            forest.collect(&mut maps, |m| m);
        }
        for (m, t) in maps.iter().zip(&trees) {
            assert_eq!(
                contents(|f| forest.for_each(m, f)),
                contents(|f| t.for_each(f)),
                "round {round}"
            );
            for h in [Hex::new(0, 0), Hex::new(5, -3), Hex::new(-29, 19)] {
                assert_eq!(forest.get(m, h), t.get(h));
            }
        }
    }
    assert!(forest.collections() >= 8);
}

#[test]
fn collection_keeps_what_maps_reach_and_frees_the_rest() {
    let mut forest: HexForest<u32> = HexForest::new();
    let mut maps = vec![ForestMap::default(); 4];
    for (i, m) in maps.iter_mut().enumerate() {
        for q in 0..64 {
            forest.leaf_mut(m, locate(Hex::new(q, 4 * i32::try_from(i).unwrap())).0)[0] =
                q as u32 + 1;
        }
    }
    let mut children = Vec::new();
    let mut next = vec![ForestMap::default(); 4];
    let new = &mut next[..];
    forest.inherit(&mut maps, |m| m, &[0, 0, 1, 1], &mut children, (new, |m| m));
    maps = next;
    let shared = forest.bytes();
    assert!(shared > 0, "parents of two share their nodes");
    assert!(maps.iter().all(|m| m.own_bytes() == 0));
    forest.collect(&mut maps, |m| m);
    assert_eq!(forest.bytes(), shared, "all still reached");
    // The children of particle 1 die: what only they reached is freed.
    maps.truncate(2);
    forest.collect(&mut maps, |m| m);
    assert!(forest.bytes() < shared);
    // A write copies the path into the writer's own nodes; the other child is unchanged.
    forest.leaf_mut(&mut maps[0], locate(Hex::new(0, 0)).0)[1] = 9;
    assert!(maps[0].own_bytes() > 0);
    for (m, nine) in maps.iter().zip([Some(9), Some(0)]) {
        assert_eq!(forest.get(m, Hex::new(63, 0)), 0, "slot 0 of the leaf only");
        assert_eq!(
            forest.leaf(m, locate(Hex::new(63, 0)).0).map(|l| l[0]),
            Some(64)
        );
        assert_eq!(forest.leaf(m, locate(Hex::new(0, 0)).0).map(|l| l[1]), nine);
    }
    maps.clear();
    forest.collect(&mut maps, |m| m);
    assert_eq!(forest.bytes(), 0);
}
