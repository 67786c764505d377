//! Parts of a system that no link joins, simulated apart ([`Components`]): the split
//! itself, each part's run against the same part simulated alone (to the bit), two
//! threads against one, grabs routed to their part, and failures naming their part.

use dae_particles::{
    Backend, BackendError, Components, Dbsmc, Edge, FRAME, ParticleModel, Scene, System, chain,
    parts, strands,
};

/// `system` twice, the copies at the same place (nothing couples them but the
/// numbering: the second copy's particles and links follow the first's).
fn twice(system: &System) -> System {
    let n = system.n_particles();
    let positions = [system.positions(), system.positions()].concat();
    let masses = [system.masses(), system.masses()].concat();
    let edges: Vec<Edge> = (0..2)
        .flat_map(|copy| {
            system.links().iter().map(move |l| Edge {
                a: l.a + copy * n,
                b: l.b + copy * n,
                rest: Some(l.rest),
            })
        })
        .collect();
    let mut both = System::from_edges(positions, masses, &edges)
        .unwrap()
        .with_velocities([system.velocities(), system.velocities()].concat())
        .unwrap()
        .with_gravity(system.gravity());
    for (k, pin) in system.pins().iter().enumerate() {
        if let Some(pin) = pin {
            both = both.with_pin(k, pin.clone()).unwrap();
            both = both.with_pin(k + n, pin.clone()).unwrap();
        }
    }
    both
}

#[test]
fn the_parts_of_the_hair_are_its_strands() {
    let hair = strands(5, 8).unwrap();
    let split = parts(&hair).unwrap();
    assert_eq!(split.len(), 5);
    for (s, part) in split.iter().enumerate() {
        assert_eq!(part.particles, (9 * s..9 * s + 9).collect::<Vec<_>>());
        assert_eq!(part.links, (8 * s..8 * s + 8).collect::<Vec<_>>());
        assert_eq!(part.system.n_particles(), 9);
        for (i, &k) in part.particles.iter().enumerate() {
            assert_eq!(part.system.positions()[i], hair.positions()[k]);
            assert_eq!(part.system.masses()[i], hair.masses()[k]);
            assert_eq!(part.system.pins()[i].is_some(), hair.pins()[k].is_some());
        }
        for (j, &l) in part.links.iter().enumerate() {
            let (a, b) = (part.system.links()[j], hair.links()[l]);
            assert_eq!(
                (part.particles[a.a], part.particles[a.b], a.rest),
                (b.a, b.b, b.rest)
            );
        }
    }
    // A connected system is one part, with every particle and link.
    let one = parts(&chain(10, 1.0).unwrap()).unwrap();
    assert_eq!(one.len(), 1);
    assert_eq!(one[0].particles.len(), 11);
}

#[test]
fn particles_without_a_constraint_join_the_first_part() {
    // Two links: 0-1 with a free end, and 2-3 between two pins; particle 4 is alone.
    let positions = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 2.0, 0.0],
    ];
    let sys = System::from_edges(positions, vec![1.0; 5], &[(0, 1), (2, 3)])
        .unwrap()
        .with_fixed(0)
        .unwrap()
        .with_fixed(2)
        .unwrap()
        .with_fixed(3)
        .unwrap();
    let split = parts(&sys).unwrap();
    assert_eq!(split.len(), 1, "{split:?}");
    assert_eq!(split[0].particles, vec![0, 1, 2, 3, 4]);
    assert_eq!(split[0].links, vec![0, 1]);
}

#[test]
fn each_part_runs_as_it_would_alone_to_the_bit() {
    let one = chain(10, 1e2).unwrap();
    let both = twice(&one);
    let mut apart = Components::online(&both, 1e-3, "apart").unwrap();
    let mut alone = Dbsmc::online(ParticleModel::new(&one).unwrap(), 1e-3, "alone").unwrap();
    let (mut p_apart, mut p_alone) = (vec![[0.0; 3]; 22], vec![[0.0; 3]; 11]);
    for f in 1..=60 {
        let t = f as f64 * FRAME;
        apart.advance_to(t).unwrap();
        alone.advance_to(t).unwrap();
        apart.positions(&mut p_apart);
        alone.positions(&mut p_alone);
        assert_eq!(&p_apart[..11], &p_alone[..], "frame {f}");
        assert_eq!(&p_apart[11..], &p_alone[..], "frame {f}");
    }
    let (c_apart, c_alone) = (apart.counters(), alone.counters());
    assert_eq!(c_apart.steps, 2 * c_alone.steps);
    assert_eq!(c_apart.f_evals, 2 * c_alone.f_evals);
    assert_eq!(c_apart.updates(), 2 * c_alone.updates());
    assert!(c_alone.updates() > 10, "{c_alone:?}");
    assert_eq!(c_apart.sliding.unwrap().parts, 2);
    assert_eq!(c_alone.sliding.unwrap().parts, 1);
    assert_eq!(apart.time(), 60.0 * FRAME);
}

#[test]
fn two_threads_give_the_results_of_one() {
    let hair = strands(6, 8).unwrap();
    let run = |threads: usize| {
        let mut b = Components::online(&hair, 1e-3, "hair")
            .unwrap()
            .threads(threads);
        for f in 1..=20 {
            b.advance_to(f as f64 * FRAME).unwrap();
        }
        let mut p = vec![[0.0; 3]; hair.n_particles()];
        b.positions(&mut p);
        (p, b.counters())
    };
    let (p1, c1) = run(1);
    let (p2, c2) = run(2);
    assert_eq!(p1, p2);
    assert_eq!(c1, c2);
    assert_eq!(c1.sliding.unwrap().parts, 6);
}

#[test]
fn a_grab_goes_to_its_part_and_the_strain_holds() {
    let one = chain(10, 1e2).unwrap();
    let both = twice(&one);
    let eps = 1e-3;
    let mut apart = Scene::new(&both, Components::online(&both, eps, "apart").unwrap()).unwrap();
    let alone_backend = Dbsmc::online(ParticleModel::new(&one).unwrap(), eps, "alone").unwrap();
    let mut alone = Scene::new(&one, alone_backend).unwrap();
    for _ in 0..10 {
        apart.step().unwrap();
        alone.step().unwrap();
    }
    // The end of the second copy (particle 21) and of the chain alone (10).
    apart.grab(21, [0.0, 0.0, 0.1], 0.2).unwrap();
    alone.grab(10, [0.0, 0.0, 0.1], 0.2).unwrap();
    for _ in 0..15 {
        apart.step().unwrap();
        alone.step().unwrap();
    }
    apart.release(21).unwrap();
    alone.release(10).unwrap();
    for _ in 0..10 {
        apart.step().unwrap();
        alone.step().unwrap();
    }
    assert_eq!(&apart.positions()[11..], alone.positions());
    assert_ne!(
        &apart.positions()[..11],
        alone.positions(),
        "the first copy was not grabbed"
    );
    assert!(
        apart.worst_strain().strain <= 1.05 * eps,
        "{:?}",
        apart.worst_strain()
    );
}

#[test]
fn a_failure_names_its_part() {
    let hair = strands(3, 4).unwrap();
    let err = Components::new(&hair, |part, p| {
        if p == 1 {
            Err(BackendError {
                method: "test".into(),
                t: 0.0,
                reason: "refused".into(),
                deadline: false,
            })
        } else {
            Dbsmc::online(ParticleModel::new(&part.system).unwrap(), 1e-3, "test")
        }
    })
    .unwrap_err();
    assert!(
        err.reason
            .starts_with("refused (in part 1 of 3, the system's particles 5 to 9;"),
        "{}",
        err.reason
    );
    let mut b = Components::online(&hair, 1e-3, "hair").unwrap();
    let err = b.set_pin(15, None).unwrap_err();
    assert!(
        err.reason.contains("particle 15 does not exist"),
        "{}",
        err.reason
    );
}

#[test]
fn the_whole_system_as_one_part_is_one_simulator_to_the_bit() {
    let hair = strands(3, 4).unwrap();
    let mut whole = Components::whole(&hair, |part, _| {
        Dbsmc::online(ParticleModel::new(&part.system).unwrap(), 1e-3, "whole")
    })
    .unwrap();
    let mut one = Dbsmc::online(ParticleModel::new(&hair).unwrap(), 1e-3, "one").unwrap();
    for f in 1..=20 {
        whole.advance_to(f as f64 * FRAME).unwrap();
        one.advance_to(f as f64 * FRAME).unwrap();
    }
    let (mut a, mut b) = (vec![[0.0; 3]; 15], vec![[0.0; 3]; 15]);
    whole.positions(&mut a);
    one.positions(&mut b);
    assert_eq!(a, b);
    assert_eq!(whole.counters(), one.counters());
}
