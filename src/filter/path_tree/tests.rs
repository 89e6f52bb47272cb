//! Tests of the path tree.

use super::*;

#[test]
fn stored_steps_are_lossless() {
    let certain = SmoothedStep {
        estimate: Some(Cluster {
            x: 1.25,
            y: -3.5,
            z: 6.0,
            level: 2,
            heading: 0.3,
            spread: 0.7,
            weight: 0.99,
            particles: 512,
        }),
        hypotheses: 1,
        certain: true,
        ancestors: 40,
    };
    let unsure = SmoothedStep {
        certain: false,
        hypotheses: 3,
        ..certain
    };
    let bare = SmoothedStep {
        ancestors: 7,
        ..SmoothedStep::NONE
    };
    for s in [certain, unsure, bare, SmoothedStep::NONE] {
        assert_eq!(StoredStep::store(&s).get(), s);
    }
    assert_eq!(std::mem::size_of::<StoredStep>(), 64);
}

use crate::map::TopologyConfig;

fn topology() -> FloorTopology {
    let tower = crate::sim::Tower::new(&Default::default()).expect("tower");
    FloorTopology::build(&tower.plan, &TopologyConfig::default()).expect("topology")
}

fn node(x: f32) -> PathNode {
    PathNode::new(x, 0.0, 0)
}

#[test]
fn pruning_keeps_exactly_the_ancestors_of_the_last_generation() {
    let topo = topology();
    let cluster = ClusterConfig::default();
    let mut tree = PathTree::new(0);
    tree.root(0, (0..4).map(|i| node(i as f32)).collect(), &topo, &cluster);
    // Generation 1: everybody descends from 1 and 3.
    tree.push(
        (0..4).map(|i| node(10.0 + i as f32)),
        &[1, 1, 3, 3],
        &topo,
        &cluster,
    );
    assert_eq!(tree.generations[0].len(), 2);
    assert_eq!(tree.generations[0][0].x, 1.0);
    assert_eq!(tree.generations[0][1].x, 3.0);
    // Generation 2: everybody descends from generation 1's node 2 (child of 3).
    tree.push(
        (0..3).map(|i| node(20.0 + i as f32)),
        &[2, 2, 2],
        &topo,
        &cluster,
    );
    assert_eq!(tree.nodes(), 1 + 1 + 3);
    // The two one-node generations are the chain now.
    assert_eq!(tree.chain.len(), 2);
    assert_eq!(tree.chain[0].x, 3.0);
    assert_eq!(tree.chain[1].x, 12.0);
    assert_eq!(tree.generations.len(), 1);
    assert_eq!(tree.generations[0][0].parent, 0);
    assert_eq!(tree.steps(), 3);
    assert_eq!(tree.peak_nodes(), 9);
}

#[test]
fn smoothed_steps_follow_the_surviving_line() {
    let topo = topology();
    let cluster = ClusterConfig::default();
    let mut tree = PathTree::new(0);
    // Two hypotheses 30 m apart; the left one dies at step 2.
    tree.root(
        0,
        vec![node(0.0), node(0.0), node(30.0), node(30.0)],
        &topo,
        &cluster,
    );
    tree.push(
        vec![node(1.0), node(1.0), node(31.0), node(31.0)],
        &[0, 1, 2, 3],
        &topo,
        &cluster,
    );
    let filtered = tree.smoothed(&topo, &cluster);
    assert_eq!(filtered[1].hypotheses, 2);
    assert!(!filtered[1].certain);
    tree.push(vec![node(32.0); 4], &[2, 2, 3, 3], &topo, &cluster);
    let s = tree.smoothed(&topo, &cluster);
    assert_eq!(s.len(), 3);
    for (k, x) in [(0, 30.0), (1, 31.0), (2, 32.0)] {
        let e = s[k].estimate.expect("estimate");
        assert!((e.x - x).abs() < 1e-6, "step {k}: {}", e.x);
        assert!(s[k].certain && s[k].hypotheses == 1);
    }
}

#[test]
fn a_cut_settles_the_steps_before_it() {
    let topo = topology();
    let cluster = ClusterConfig::default();
    let mut tree = PathTree::new(0);
    tree.root(0, vec![node(5.0)], &topo, &cluster);
    tree.push(vec![node(6.0)], &[0], &topo, &cluster);
    tree.push(vec![node(7.0)], &[0], &topo, &cluster);
    // Re-seeded at step 2: steps 0 and 1 keep their answer, 2 is replaced.
    tree.root(2, vec![node(40.0)], &topo, &cluster);
    tree.push(vec![node(41.0)], &[0], &topo, &cluster);
    let s = tree.smoothed(&topo, &cluster);
    let xs: Vec<f64> = s.iter().map(|k| k.estimate.expect("e").x).collect();
    assert_eq!(xs, vec![5.0, 6.0, 40.0, 41.0]);
    // A fresh start after the end leaves no gap unexplained.
    tree.root(6, vec![node(50.0)], &topo, &cluster);
    let s = tree.smoothed(&topo, &cluster);
    assert_eq!(s.len(), 7);
    assert!(s[4].estimate.is_none() && s[5].estimate.is_none());
    assert_eq!(s[3].estimate.expect("kept").x, 41.0);
}

/// Children linked to random parents: `sorted` in increasing order (as resampling links
/// them) or shuffled; some parents left childless.
fn random_links(rng: &mut rand_pcg::Pcg64Mcg, parents: usize, sorted: bool) -> Vec<PathNode> {
    use rand::RngExt;
    let children = rng.random_range(0..3 * parents + 2);
    let mut links: Vec<u32> = (0..children)
        .map(|_| rng.random_range(0..parents as u32))
        .collect();
    if sorted {
        links.sort_unstable();
    }
    links
        .into_iter()
        .enumerate()
        .map(|(i, p)| PathNode {
            parent: p,
            ..node(i as f32)
        })
        .collect()
}

#[test]
fn pruning_in_order_matches_pruning_through_the_remap() {
    let mut rng = crate::random::stream(7, 0, 0);
    for case in 0..400 {
        let m = 1 + case % 37;
        let parents: Vec<PathNode> = (0..m).map(|i| node(100.0 + i as f32)).collect();
        let children = random_links(&mut rng, m, true);
        let (mut p1, mut c1) = (parents.clone(), children.clone());
        let (mut p2, mut c2) = (parents.clone(), children);
        let lost = prune_sorted(&mut p1, &mut c1).expect("links in order");
        assert_eq!(
            lost,
            prune_any(&mut p2, &mut c2, &mut Vec::new()),
            "case {case}"
        );
        assert_eq!((p1, c1), (p2, c2), "case {case}");
    }
}

#[test]
fn links_out_of_order_are_left_to_the_remap() {
    let mut rng = crate::random::stream(8, 0, 0);
    let parents: Vec<PathNode> = (0..20).map(|i| node(i as f32)).collect();
    let mut children = random_links(&mut rng, 20, true);
    children.reverse();
    children.push(PathNode {
        parent: 19,
        ..node(0.0)
    });
    children.push(PathNode {
        parent: 0,
        ..node(0.0)
    });
    let (mut p, mut c) = (parents.clone(), children.clone());
    assert_eq!(prune_sorted(&mut p, &mut c), None);
    assert_eq!((p, c), (parents.clone(), children));
    // A child without a parent, too.
    let mut orphan = vec![PathNode::new(0.0, 0.0, 0)];
    let mut p = parents.clone();
    assert_eq!(prune_sorted(&mut p, &mut orphan), None);
    assert_eq!(p, parents);
}
