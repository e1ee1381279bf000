# SPDX-License-Identifier: BSD-3-Clause
"""Steps from Python equal `smpm run` bit for bit; the run loop and its callback."""
import re
import threading
import time

import h5py
import numpy as np
import pytest

import sparsempm as smpm

from conftest import BAR, SOURCE, TWO_BLOCKS, interrupting, run_smpm

# 100 steps of the bar: Δt = C Δx / c = 0.5 · 1 / 2 = 0.25 (the wave speed exceeds |V| ≤ 0.16),
# so t = 25 is reached in exactly 100 steps, and one frame at its end.
OVERRIDES = {"time.end": 25.0, "output.every": 25.0}


@pytest.fixture(scope="module")
def cli_frame(tmp_path_factory):
    """Positions and velocities after 100 FLIP steps written by `smpm run`."""
    out = tmp_path_factory.mktemp("run") / "bar.h5"
    r = run_smpm("run", BAR, "-q", "-o", out, *[f"--set={k}={v}" for k, v in OVERRIDES.items()])
    assert r.returncode == 0, r.stderr
    with h5py.File(out, "r") as f:
        frame = f["particles"]["000001"]
        assert frame.attrs["step"] == 100 and frame.attrs["time"] == 25.0
        assert f["series"]["step"][-1] == 100
        return frame["X"][...], frame["V"][...], f["series"]["total"][-1]


def test_stepper_equals_smpm_run_bit_for_bit(cli_frame):
    model = smpm.Model.from_toml(str(BAR), OVERRIDES)
    assert model.options.velocity == "FLIP" and model.options.shape == "cpdi"
    stepper = smpm.Stepper(model.options)
    for _ in range(100):
        stepper.step(model, smpm.stable_time_step(model, model.courant))
    assert model.step == 100 and model.time == 25.0
    X, V, _ = cli_frame
    # The same library calls in the same order: identical doubles.
    assert np.array_equal(model.particles.X, X)
    assert np.array_equal(model.particles.V, V)


def test_advance_equals_smpm_run_bit_for_bit(cli_frame):
    model = smpm.Model.from_toml(str(BAR), OVERRIDES)
    seen = []
    report = smpm.Stepper(model.options).advance(
        model, model.end, model.courant, lambda m, e, at_stop: seen.append((m.step, e.total, at_stop)),
        stop_every=25.0)
    assert report.steps == 100 and len(seen) == 100
    assert seen[-1][0] == 100 and seen[-1][2] and not any(s[2] for s in seen[:-1])
    X, V, total = cli_frame
    # The callback's energy is the total of the run's series (the same sums).
    assert seen[-1][1] == total == report.energy_end
    assert np.array_equal(model.particles.X, X) and np.array_equal(model.particles.V, V)


def test_callback_that_changes_velocities_sets_the_next_time_step():
    # The bar's Δt = C Δx / 2 = 0.25 until the callback gives a particle the speed 50 after the
    # first step: the second step has Δt = C Δx / 50 = 0.01 (FMPM 2026 §3.3's Courant relation
    # evaluated on the changed model).
    model = smpm.Model.from_toml(str(BAR))
    times = []

    def kick(m, e, at_stop):
        times.append(m.time)
        if len(times) == 1:
            m.particles.V[3, 0] = 50.0

    smpm.Stepper(model.options).advance(model, 0.3, 0.5, kick, energy_growth=0.0)
    assert times[0] == 0.25
    assert times[1] - times[0] == pytest.approx(0.01, rel=1e-12)


def test_callback_exception_stops_the_run():
    model = smpm.Model.from_toml(str(BAR))

    def stop(m, e, at_stop):
        if m.step == 3:
            raise KeyboardInterrupt("stop here")

    with pytest.raises(KeyboardInterrupt, match="stop here"):
        smpm.Stepper(model.options).advance(model, 10.0, 0.5, stop)
    assert model.step == 3


def test_steps_run_in_parallel_threads():
    # The GIL is released during steps: two models stepped on two threads give each the result
    # of stepping it alone (bit for bit).
    def run(model, n):
        s = smpm.Stepper(model.options)
        for _ in range(n):
            s.step(model, 0.25)

    alone = smpm.Model.from_toml(str(BAR))
    run(alone, 200)
    models = [smpm.Model.from_toml(str(BAR)) for _ in range(2)]
    threads = [threading.Thread(target=run, args=(m, 200)) for m in models]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for m in models:
        assert np.array_equal(m.particles.X, alone.particles.X)


def longest_pause_of_python(call):
    """Runs call() on a thread while this thread records the time in a loop; returns the
    longest pause between two records and the duration of the call. A call holding the GIL
    pauses this loop for its whole duration."""
    done = threading.Event()
    span = []

    def worker():
        t0 = time.perf_counter()
        call()
        span.append(time.perf_counter() - t0)
        done.set()

    t = threading.Thread(target=worker)
    stamps = [time.perf_counter()]
    t.start()
    while not done.is_set():
        stamps.append(time.perf_counter())
    t.join()
    return np.diff(stamps).max(), span[0]


@pytest.mark.parametrize("what", ["advance", "sweep_shifts"])
def test_gil_released(what):
    model = smpm.Model.from_toml(str(BAR))
    o = model.options.copy()
    o.velocity, o.order = "FMPM", 20
    calls = {"advance": lambda: smpm.Stepper(o).advance(model, 400.0, 0.2),
             "sweep_shifts": lambda: smpm.sweep_shifts(model, o, 4)}
    pause, duration = longest_pause_of_python(calls[what])
    # The loop kept running: its longest pause (a scheduler slice, ~ms) is far below the
    # duration of the call (0.1-0.5 s), which a held GIL would have blocked it for.
    assert duration > 0.05 and pause < 0.5 * duration


def test_shock_energy_equals_smpm_run_bit_for_bit(tmp_path):
    # The Mie-Gruneisen split bar (examples/shock_split_bar.toml) to its second frame: the
    # internal energies U (a numpy view of the particles) equal the frame's `energy` of
    # `smpm run`, and the shock has heated the material behind it (U > 1e6 mm²/ms², the
    # Rankine-Hugoniot u_p²/2 = 1.69e6).
    src = BAR.parent / "shock_split_bar.toml"
    over = {"time.end": 0.000434, "output.every": 0.000434}
    out = tmp_path / "shock.h5"
    r = run_smpm("run", src, "-q", "-o", out, *[f"--set={k}={v}" for k, v in over.items()])
    assert r.returncode == 0, r.stderr
    model = smpm.Model.from_toml(str(src), over)
    smpm.Stepper(model.options).advance(model, model.end, model.courant, stop_every=0.000434)
    with h5py.File(out, "r") as f:
        frame = f["particles"]["000001"]
        assert np.array_equal(model.particles.energy, frame["energy"][...])
        assert np.array_equal(model.particles.X, frame["X"][...])
    assert model.particles.energy.max() > 1e6


def test_plastic_shock_equals_smpm_run_bit_for_bit(tmp_path):
    # The split bar with nickel's shear modulus and J2 plasticity to its second frame: the
    # plastic state (numpy views of the particles) equals the frame's plastic_strain and
    # elastic_cauchy_green of `smpm run`, and the particles behind the shock have flowed.
    src = BAR.parent / "shock_split_bar.toml"
    over = {"time.end": 0.000434, "output.every": 0.000434}
    for side in ("left", "right"):
        over[f"material.{side}.shear"] = 85500.0
        over[f"material.{side}.yield_stress"] = 140.0
    out = tmp_path / "plastic.h5"
    r = run_smpm("run", src, "-q", "-o", out, *[f"--set={k}={v}" for k, v in over.items()])
    assert r.returncode == 0, r.stderr
    model = smpm.Model.from_toml(str(src), over)
    assert model.materials[0].yield_stress == 140.0 and model.materials[0].hardening == 0.0
    smpm.Stepper(model.options).advance(model, model.end, model.courant, stop_every=0.000434)
    with h5py.File(out, "r") as f:
        frame = f["particles"]["000001"]
        assert np.array_equal(model.particles.plastic_strain, frame["plastic_strain"][...])
        assert np.array_equal(model.particles.elastic_cauchy_green,
                              frame["elastic_cauchy_green"][...])
    assert model.particles.plastic_strain.max() > 0.1
    assert smpm.Material("p", "hyperelastic", youngs=1.0, yield_stress=0.01).yield_stress == 0.01
    with pytest.raises(smpm.InputError, match="yield_stress .J2 plasticity. is for the hyperelastic"):
        smpm.Material("p", "neo-hookean", youngs=1.0, yield_stress=0.01)


def test_one_and_two_threads_step_the_same_bits():
    """set_threads: 50 FMPM(4) steps of the block impact (8000 particles, enough for the kernels
    to use the threads) end in the same bits on 1 and 2 threads."""
    saved = smpm.threads()
    states = []
    try:
        for n in (1, 2):
            smpm.set_threads(n)
            assert smpm.threads() == n
            model = smpm.Model.from_toml(str(SOURCE / "examples" / "block_impact.toml"),
                                         {"step.velocity": "FMPM", "step.order": 4})
            stepper = smpm.Stepper(model.options)
            for _ in range(50):
                stepper.step(model, smpm.stable_time_step(model, model.courant))
            P = model.particles
            states.append([P.X.copy(), P.V.copy(), P.F.copy(), P.stress.copy()])
        with pytest.raises(smpm.InputError, match="the number of threads must lie in"):
            smpm.set_threads(0)
    finally:
        smpm.set_threads(saved)
    assert np.abs(states[0][3]).max() > 0  # the run did something: stresses
    for one, two in zip(*states):
        assert np.array_equal(one, two)


def test_fmpm_metrics_trace_the_dynamic_loop():
    # FMPM 2026 §3.4 / Fig. 13A: with a limit of 0 the loop of FMPM(12) runs to ℓ = 12 and
    # fmpm_metrics holds the metric of passes 2 … 12; with a limit between the values of
    # passes 4 and 5 the loop stops where that curve first falls below it, and its trace is the
    # curve up to there (the same doubles: same state, same passes).
    model = smpm.Model.from_toml(str(BAR), {"step.velocity": "FMPM", "step.order": 12,
                                            "step.dynamic_metric": "means",
                                            "step.dynamic_limit": 1e-3})
    stepper = smpm.Stepper(model.options)
    for _ in range(20):
        stepper.step(model, smpm.stable_time_step(model, model.courant))
    dt = smpm.stable_time_step(model, model.courant)
    full = model.options.copy()
    full.dynamic_limit = 0.0
    s = smpm.Stepper(full)
    s.step(model.copy(), dt)
    curve = s.fmpm_metrics
    assert len(curve) == 11 and s.fmpm_order == 12 and all(c > 0 for c in curve)
    limit = 0.5 * (curve[2] + curve[3])
    expected = next(ell for ell, c in enumerate(curve, start=2) if c < limit)
    early = model.options.copy()
    early.dynamic_limit = limit
    s = smpm.Stepper(early)
    s.step(model.copy(), dt)
    assert s.fmpm_order == expected and s.fmpm_metrics == curve[:expected - 1]


def test_grid_velocity_rows_are_the_grid_nodes_of_the_step():
    # A step works on the window of the grid its particles reach (StepOptions.nodes): the bar
    # (x from 0 to 40, CPDI) on a grid from x = -100 of 300 cells uses the 48 nodes from
    # x = -4 (node 96, a multiple of 8) to 43. On the first FLIP step the stress is zero, so
    # v⁺ = m⁻¹ Sᵀ M V on every node but the fixed one (x = 0, node 100): the rows of
    # grid_velocity equal, bit for bit, those of the whole grid's operators at grid_nodes.
    model = smpm.Model.from_toml(str(BAR), {"grid.cells": [300], "grid.origin": [-100.0]})
    ops = smpm.assemble(model)
    v = ops.momentum(model.particles.V) * ops.m_inv[:, None]
    stepper = smpm.Stepper(model.options)
    stepper.step(model, 0.25)
    nodes = stepper.grid_nodes
    assert len(nodes) == 48 and stepper.grid_velocity.shape == (48, 1)
    np.testing.assert_array_equal(nodes, 96 + np.arange(48))
    assert set(ops.active_nodes) <= set(nodes)
    free = nodes != 100
    np.testing.assert_array_equal(stepper.grid_velocity[free], v[nodes[free]])
    assert np.abs(v[nodes[free]]).max() > 0.1  # the bar moves
    assert stepper.grid_velocity[~free, 0] == 0.0


def test_a_step_on_every_grid_node_equals_the_step_on_the_window():
    # StepOptions.nodes = "grid" puts a step on all 301 nodes of the grid above instead of the
    # window of 48: grid_nodes is then 0 ... 300, and after five FLIP steps the rows at the
    # window's nodes and the particles equal the window's run bit for bit (the window renumbers
    # the nodes monotonically, so every nodal sum adds the same terms in the same order), while
    # the nodes outside the window carry no velocity.
    runs = {}
    for nodes in ("particles", "grid"):
        model = smpm.Model.from_toml(str(BAR), {"grid.cells": [300], "grid.origin": [-100.0]})
        options = model.options.copy()
        options.nodes = nodes
        assert options.nodes == nodes
        stepper = smpm.Stepper(options)
        for _ in range(5):
            stepper.step(model, 0.25)
        runs[nodes] = (stepper.grid_nodes, stepper.grid_velocity.copy(), model.particles.X.copy(),
                       model.particles.V.copy())
    window, v_window, X_window, V_window = runs["particles"]
    every, v_every, X_every, V_every = runs["grid"]
    np.testing.assert_array_equal(every, np.arange(301))
    assert len(window) == 48
    np.testing.assert_array_equal(v_every[window], v_window)
    outside = np.setdiff1d(every, window)
    assert not v_every[outside].any()
    np.testing.assert_array_equal(X_every, X_window)
    np.testing.assert_array_equal(V_every, V_window)
    assert smpm.StepOptions(nodes="grid").nodes == "grid"
    with pytest.raises(smpm.InputError, match="unknown node range 'all' .expected particles . grid."):
        smpm.StepOptions(nodes="all")


def test_step_options_take_the_keys_of_the_step_table():
    # One vocabulary: StepOptions(**options) takes the [step] keys of the input files, each also
    # an attribute; the limits are the library's (validate), as in the input files.
    o = smpm.StepOptions(scheme="USF", velocity="FMPM", order=4, blend_alpha=0.8,
                         xpic_contact="term", exact_mass_cutoff=0.01)
    assert (o.scheme, o.velocity, o.order, o.blend_alpha) == ("USF", "FMPM", 4, 0.8)
    assert o.xpic_contact == "term" and o.exact_mass_cutoff == 0.01
    assert smpm.StepOptions().shape == "cpdi"  # the default of the input files
    with pytest.warns(DeprecationWarning, match="'xpic_contact_term' is the earlier name"):
        assert smpm.StepOptions(xpic_contact_term=False).xpic_contact == "none"
    with pytest.warns(DeprecationWarning, match="'update' is the earlier name of 'scheme'"):
        assert smpm.StepOptions(update="USL+").scheme == "USL+"
    with pytest.raises(smpm.InputError, match="unknown option 'oder'"):
        smpm.StepOptions(oder=4)
    with pytest.raises(smpm.InputError, match="order = 0: must be an integer from 1 to 100000"):
        smpm.StepOptions(order=0)


@pytest.mark.parametrize("example,steps", [("two_block_compression.toml", 30),
                                           ("shock_split_bar.toml", 30),
                                           ("moving_wall_mms.toml", 30),
                                           ("disk_impact.toml", 10)])
def test_every_table_of_an_input_from_python(example, steps):
    # Python reaches everything TOML does: the model of an example rebuilt from arrays, its
    # [[material]] tables as Material(**keys) (Mie-Gruneisen included), its [[bc]] tables through
    # add_bc (fixed planes, moving walls), its [[contact]] tables through set_contact, [loads]
    # gravity and [step] as StepOptions(**keys), steps as `smpm run` does, bit for bit.
    import tomllib
    path = SOURCE / "examples" / example
    tables = tomllib.loads(path.read_text())
    ref = smpm.Model.from_toml(str(path))
    P = ref.particles
    materials = [smpm.Material(t["name"], t.get("model", "linear"),
                               **{k: v for k, v in t.items() if k not in ("name", "model")})
                 for t in tables["material"]]
    model = smpm.Model(ref.grid, P.X, P.mass, P.volume0, V=P.V, material=P.material,
                       materials=materials, half_length=P.half_length,
                       gravity=tables.get("loads", {}).get("gravity", []))
    for bc in tables.get("bc", []):
        model.add_bc(bc)
    if "contact" in tables:
        model.set_contact(tables["contact"])
    assert model.velocity_fields == ref.velocity_fields
    assert len(model.bcs) == len(ref.bcs) and model.bcs.walls == ref.bcs.walls
    options = smpm.StepOptions(**tables.get("step", {}))
    assert repr(options) == repr(ref.options)
    for m, o in ((ref, ref.options), (model, options)):
        stepper = smpm.Stepper(o)
        for _ in range(steps):
            stepper.step(m, smpm.stable_time_step(m, ref.courant))
    for name in ("X", "V", "F", "stress", "energy"):
        assert np.array_equal(getattr(model.particles, name), getattr(ref.particles, name)), name


def test_earlier_python_names_warn_and_mean_the_same():
    # The renames of one vocabulary (docs/guide/vocabulary.md): k, alpha, every, volume, body_force, t_end and the
    # input's step.update / [scheme] still work in this release, each with a DeprecationWarning.
    bar = smpm.Model.from_toml(str(BAR))
    ops = smpm.assemble(bar)
    p = ops.momentum(bar.particles.V)
    with pytest.warns(DeprecationWarning, match="'k' is the earlier name of 'order'"):
        old = smpm.fmpm_velocity(ops, p, k=4, alpha=0.8, every=2)
    assert np.array_equal(old, smpm.fmpm_velocity(ops, p, order=4, blend_alpha=0.8, blend_every=2))
    grid = smpm.Grid(cells=[4])
    with pytest.warns(DeprecationWarning, match="'volume' is the earlier name of 'volume0'"):
        m = smpm.Model(grid, X=[1.5, 2.5], mass=[1, 1], volume=[1, 1], materials=[smpm.Material()],
                       body_force=[-1.0])
    assert list(m.particles.volume0) == [1, 1] and m.gravity == [-1.0]
    a, b = bar.copy(), bar.copy()
    with pytest.warns(DeprecationWarning, match="'t_end' is the earlier name of 'end'"):
        smpm.Stepper(a.options).advance(a, t_end=4.0, courant=0.5)
    smpm.Stepper(b.options).advance(b, end=4.0, courant=0.5)
    assert np.array_equal(a.particles.V, b.particles.V)
    with pytest.warns(DeprecationWarning, match="--set scheme.velocity is now --set step.velocity"):
        assert smpm.Model.from_toml(str(BAR), {"scheme.velocity": "PIC"}).options.velocity == "PIC"


def test_a_stepper_belongs_to_one_thread(bar):
    # advance() holds its Stepper for the whole run: a step of another model from a second
    # thread in the middle of it used to run, on the same operators and grid fields as the run;
    # now it is refused and the run goes on as if it had not been tried.
    other = smpm.Model.from_toml(str(BAR))
    reference = smpm.Model.from_toml(str(BAR))
    smpm.Stepper(reference.options).advance(reference, end=25.0, callback=lambda *a: None)
    stepper = smpm.Stepper(bar.options)
    started, tried, refused = threading.Event(), threading.Event(), []

    def callback(model, energies, at_stop):
        if not started.is_set():
            started.set()
            tried.wait(60)  # releases the GIL: the second thread steps now

    def second():
        started.wait(60)
        try:
            stepper.step(other, 0.25)
        except smpm.UsageError as e:
            refused.append(str(e))
        try:  # nor read its grid fields while the run resizes them
            stepper.grid_velocity
        except smpm.UsageError as e:
            refused.append(str(e))
        tried.set()

    thread = threading.Thread(target=second)
    thread.start()
    stepper.advance(bar, end=25.0, callback=callback)
    thread.join()
    assert len(refused) == 2 and all("a Stepper belongs to one thread at a time" in m
                                     for m in refused)
    assert other.step == 0 and bar.step == 100
    np.testing.assert_array_equal(bar.particles.V, reference.particles.V)
    np.testing.assert_array_equal(bar.particles.X, reference.particles.X)
    # Once the run is over, the other thread may take the Stepper.
    thread = threading.Thread(target=stepper.step, args=(other, 0.25))
    thread.start()
    thread.join()
    assert other.step == 1


def test_ctrl_c_stops_advance_after_the_step_in_progress(bar):
    # advance() runs with the GIL released: Python's SIGINT handler used to run only when the
    # whole run (here 10 million steps) had ended. Now the run stops after the step in progress
    # with KeyboardInterrupt and the model is left at that step.
    # At C = 0.1 (Δt = 0.05, see OVERRIDES) FLIP stays stable for the 10 million steps.
    end = 1e7 * 0.05
    started = threading.Event()  # Ctrl-C only once the run is under way
    with interrupting(started=started):
        with pytest.raises(KeyboardInterrupt):
            smpm.Stepper(bar.options).advance(bar, end=end, courant=0.1,
                                              callback=lambda *a: started.set())
    assert 0 < bar.time < end and bar.step > 0
    assert bar.time == pytest.approx(0.05 * bar.step)
    assert np.isfinite(bar.particles.V).all()


@pytest.mark.parametrize("shape", ["linear", "gimp", "bspline2", "cpdi", "b2cpdi"])
def test_bonded_contact_is_single_material_mode_for_every_shape(tmp_path, shape):
    # Contact 2020 §3.2: stick contact detected everywhere reverts to single material mode. The
    # two blocks of contact 2020 §2.3 bonded, 60 FLIP steps and 60 PIC steps, against the same
    # blocks as one velocity field: equal to round-off for every shape. With uGIMP a field whose
    # share of a node fell below 1e-10 of the largest nodal mass was switched off there, dropping
    # its internal force: 1.8e-8 of max|V| (the other shapes: 1e-13).
    text = TWO_BLOCKS.read_text()
    text = text.replace('law = "coulomb"', 'law = "stick"').replace("friction = 0.2\n", "")
    text = re.sub(r'detection = "CP".*', 'detection = "always"', text)
    bonded = tmp_path / "bonded.toml"
    bonded.write_text(text)
    for velocity in ("FLIP", "PIC"):
        runs = []
        for law in ("stick", "single-field"):
            model = smpm.Model.from_toml(str(bonded), {"step.shape": shape,
                                                       "step.velocity": velocity,
                                                       "contact.0.law": law})
            stepper = smpm.Stepper(model.options)
            dt = smpm.stable_time_step(model, 0.5)
            for _ in range(60):
                stepper.step(model, dt)
            runs.append(model.particles)
        bonded_V, single_V = runs[0].V, runs[1].V
        scale = np.abs(single_V).max()
        assert scale > 0
        assert np.abs(bonded_V - single_V).max() < 1e-11 * scale, (velocity, shape)
        momentum = [p.mass @ p.V for p in runs]
        momentum_scale = (runs[1].mass @ np.abs(single_V)).max()
        assert np.abs(momentum[0] - momentum[1]).max() < 1e-11 * momentum_scale


def test_contact_law_at_one_node():
    # contact_momentum_change is the law every contact step calls (FMPM 2026 Eq. 18): with
    # N_c = −Δp(0)·n̂ and T_c = |Δp(0)_t| (per A_c Δt), Δp = −N_c n̂ + min(T_c, μ N_c) t̂ when the
    # fields approach and touch, none otherwise; stick gives Δp(0), frictionless its normal part.
    rng = np.random.default_rng(3)
    for d in (2, 3):
        for _ in range(200):
            n = rng.normal(size=d)
            n /= np.linalg.norm(n)
            dp0 = rng.normal(size=d)
            mu = rng.uniform(0, 1.5)
            dn = dp0 @ n
            tangential = dp0 - dn * n
            t_c = np.linalg.norm(tangential)
            touching, dp = smpm.contact_momentum_change(list(dp0), list(n), "coulomb", mu, -0.1)
            assert touching == (dn < 0)
            if dn < 0:
                expected = dn * n + min(t_c, -mu * dn) / t_c * tangential
                assert np.abs(np.array(dp) - expected).max() <= 1e-14 * np.abs(dp0).max()
            else:
                assert dp == [0.0] * d
            _, stick = smpm.contact_momentum_change(list(dp0), list(n), "stick", 0.0, -0.1)
            assert stick == (list(dp0) if dn < 0 else [0.0] * d)
            _, slip = smpm.contact_momentum_change(list(dp0), list(n), "frictionless", 0.0, -0.1)
            assert np.abs(np.array(slip) - (dn * n if dn < 0 else 0)).max() <= 1e-15
            apart, none = smpm.contact_momentum_change(list(dp0), list(n), "coulomb", mu, 0.1)
            assert not apart and none == [0.0] * d  # separated: no contact
    with pytest.raises(smpm.InputError, match="friction = -1: must be non-negative"):
        smpm.contact_momentum_change([1.0, 0.0], [0.0, 1.0], "coulomb", -1.0)
    with pytest.raises(smpm.InputError, match="same 1 to 3 components"):
        smpm.contact_momentum_change([1.0, 0.0], [0.0, 1.0, 0.0])
