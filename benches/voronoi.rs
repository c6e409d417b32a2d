//! Criterion bench of the Voronoi stage: rasterise, brushfire, graph, on 1024 x 1024 and
//! 4096 x 4096 cells with 50 compound obstacles; and a local update against a rebuild.

use criterion::{Criterion, criterion_group, criterion_main};
use homospline_voronoi::{DistanceField, Grid, VoronoiGraph};
use std::hint::black_box;

#[path = "scenes.rs"]
mod scenes;

fn bench(c: &mut Criterion) {
    let scene = scenes::compound_scene(1024.0, 50, 7);
    let mut g = c.benchmark_group("voronoi");
    for (cells, resolution) in [(1024, 1.0), (4096, 4.0)] {
        let grid = Grid::from_scene(&scene, resolution).unwrap();
        let field = DistanceField::build(&grid);
        g.bench_function(format!("rasterise/{cells}"), |b| {
            b.iter(|| Grid::from_scene(black_box(&scene), resolution).unwrap())
        });
        g.bench_function(format!("brushfire/{cells}"), |b| {
            b.iter(|| DistanceField::build(black_box(&grid)))
        });
        g.bench_function(format!("graph/{cells}"), |b| {
            b.iter(|| {
                VoronoiGraph::build(
                    black_box(&grid),
                    &field,
                    Some(scene.start),
                    Some(scene.goal),
                )
                .unwrap()
            })
        });
        g.bench_function(format!("total/{cells}"), |b| {
            b.iter(|| homospline_voronoi::build(black_box(&scene), resolution).unwrap())
        });
    }
    // A small obstacle (radius 4 cells) dropped into free space, then taken away again.
    let grid = Grid::from_scene(&scene, 1.0).unwrap();
    let field = DistanceField::build(&grid);
    let (ci, cj) = (512usize, 300usize);
    let cells: Vec<(usize, usize)> = (cj - 4..=cj + 4)
        .flat_map(|j| (ci - 4..=ci + 4).map(move |i| (i, j)))
        .filter(|&(i, j)| (i as i64 - ci as i64).pow(2) + (j as i64 - cj as i64).pow(2) <= 16)
        .collect();
    assert!(
        cells.iter().all(|&(i, j)| !grid.occupied(i, j)),
        "bench obstacle must land in free space"
    );
    g.bench_function("update_add_small/1024", |b| {
        b.iter_batched(
            || (grid.clone(), field.clone()),
            |(mut gr, mut f)| f.add_obstacle(&mut gr, &cells).unwrap(),
            criterion::BatchSize::LargeInput,
        )
    });
    g.bench_function("rebuild_after_add/1024", |b| {
        let mut gr = grid.clone();
        for &(i, j) in &cells {
            gr.set(i, j, true);
        }
        b.iter(|| DistanceField::build(black_box(&gr)))
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .sample_size(10)
        .warm_up_time(std::time::Duration::from_millis(500))
        .measurement_time(std::time::Duration::from_secs(3));
    targets = bench
}
criterion_main!(benches);
