# SPDX-License-Identifier: BSD-3-Clause
"""Heat transport from Python (transport.hpp; FMPM 2026 §3.5 with the capacities in the place of
the masses): the options, materials, particle temperatures and temperature conditions of the input
files; the capacity matrices against the same products in scipy; FMPM(k) on c~ against its series
and the exact inverse; a conducting bar against the analytic series; a heated run equal to
`smpm run` bit for bit."""
import tomllib

import h5py
import numpy as np
import pytest
import scipy.linalg
import scipy.sparse

import sparsempm as smpm

from conftest import SOURCE, TWO_BLOCKS, run_smpm

SHAPES = ["linear", "gimp", "bspline2", "cpdi", "b2cpdi"]

# The vibrating bar of FMPM 2026 §3.3 heated: C_V, κ, T_ref and thermal expansion, a temperature
# field and a source, its free end held at a varying temperature, FMPM(4) with FMPM(3) on c~.
# D = κ/(ρ C_V) = 4 and Δx = 1: the conduction limit F Δx²/D = 0.05 (F = 0.2) is below the
# Courant step 0.5 Δx / 2 = 0.25, so each of the 400 steps to t = 20 is 0.05 long.
HEATED_BAR = """
[grid]
dim = 1
origin = [-2.0]
cell_size = [1.0]
cells = [48]

[[material]]
name = "bar"
model = "linear"
density = 0.5
youngs = 2.0
poisson = 0.0
heat_capacity = 2.0
conductivity = 4.0
reference_temperature = 300.0
thermal_expansion = 1e-3

[[body]]
material = "bar"
region = "box"
min = [0.0]
max = [40.0]
ppc = [2]
velocity = ["0.16*sin(pi*X/80)"]
temperature = "300 + X"
heat_source = 0.5

[[bc]]
plane = { axis = "x", at = 0.0 }
fixed = ["x"]

[[bc]]
plane = { axis = "x", at = 40.0 }
temperature = "350 + 10*sin(t)"

[time]
courant = 0.5
end = 20.0
fourier = 0.2

[step]
velocity = "FMPM"
order = 4
shape = "cpdi"
transport = "FMPM"
transport_order = 3

[output]
file = "heated_bar.h5"
every = 10.0
"""

# The heat keys of the two blocks of contact 2020 §2.3: two materials, two velocity fields, whose
# transport folds the fields' block columns onto the grid nodes.
BLOCK_HEAT = {"material.lower.heat_capacity": 2.0, "material.lower.conductivity": 3.0,
              "material.lower.reference_temperature": 300.0,
              "material.upper.heat_capacity": 0.5, "material.upper.conductivity": 1.0,
              "material.upper.reference_temperature": 300.0}


@pytest.fixture(scope="module")
def heated_bar(tmp_path_factory):
    path = tmp_path_factory.mktemp("heat") / "heated_bar.toml"
    path.write_text(HEATED_BAR)
    return path


@pytest.fixture(scope="module")
def blocks():
    """The two blocks after 20 steps (deformed, det F ≠ 1), with random temperatures and
    sources (seeded)."""
    model = smpm.Model.from_toml(str(TWO_BLOCKS), BLOCK_HEAT)
    stepper = smpm.Stepper(model.options)
    for _ in range(20):
        stepper.step(model, smpm.stable_time_step(model, model.courant))
    rng = np.random.default_rng(7)
    model.particles.temperature = 300 + 20 * rng.random(len(model.particles))
    model.particles.heat_source = rng.random(len(model.particles))
    return model


def conduction_bar(cells=40, T0=300.0, T1=400.0, T2=350.0):
    """A bar 0 ≤ x ≤ 1 (L = 1) of `cells` linear cells, 2 particles per cell, D = κ/(ρ C_V) = 1,
    at T0 with its ends held at T1 (x = 0) and T2 (x = 1); the grid reaches a cell beyond each
    end; FMPM(4) transport. The mechanics stay at rest (V = 0, E tiny)."""
    h = 1.0 / cells
    X = (np.arange(2 * cells) + 0.5) * h / 2
    bar = smpm.Material("bar", density=1.0, youngs=1e-9, poisson=0.0, heat_capacity=1.0,
                        conductivity=1.0, reference_temperature=T0)
    model = smpm.Model(smpm.Grid([cells + 2], [h], [-h]), X[:, None], mass=np.full(2 * cells, h / 2),
                       volume0=np.full(2 * cells, h / 2), materials=[bar], temperature=T0)
    assert model.add_bc({"plane": {"axis": "x", "at": 0.0}, "temperature": T1}) == 1
    assert model.add_bc({"plane": {"axis": "x", "at": 1.0}, "temperature": T2}) == 1
    model.options = smpm.StepOptions(shape="linear", transport="FMPM", transport_order=4)
    return model


def series(x, t, T0, T1, T2, terms=2000):
    """Carslaw & Jaeger §3.3 (L = D = 1): T = T1 + (T2 − T1) x + Σ_n (2/(nπ)) ((T0 − T1)(1 − (−1)ⁿ)
    + (T2 − T1)(−1)ⁿ) sin(nπx) exp(−n²π²t)."""
    n = np.arange(1, terms + 1)[:, None]
    sign = (-1.0) ** n
    B = 2 / (n * np.pi) * ((T0 - T1) * (1 - sign) + (T2 - T1) * sign)
    return T1 + (T2 - T1) * x + (B * np.sin(n * np.pi * x) * np.exp(-(n * np.pi) ** 2 * t)).sum(0)


def test_step_options_and_materials_take_the_heat_keys():
    # [step] transport and transport_order by name, each also an attribute; the library's limits
    # (validate) with its messages.
    o = smpm.StepOptions(transport="FMPM", transport_order=4)
    assert (o.transport, o.transport_order) == ("FMPM", 4)
    assert smpm.StepOptions().transport == "off"
    assert smpm.StepOptions(velocity="FMPM", order=4, transport="FMPM").transport_order == 0
    with pytest.raises(smpm.InputError, match=r"unknown transport update 'hot' \(expected off "
                                              r"\| lumped \| FMPM \| exact\)"):
        smpm.StepOptions(transport="hot")
    with pytest.raises(smpm.InputError, match=r"transport_order = 0 \(unset\): give the order k "
                                              r"of FMPM\(k\) on the capacity"):
        smpm.StepOptions(transport="FMPM")
    with pytest.raises(smpm.InputError, match="transport_order = -1: must be an integer"):
        smpm.StepOptions(transport="lumped", transport_order=-1)
    # transport_limiter: 'none' (default) | 'fct', for FMPM transport without blending.
    assert smpm.StepOptions().transport_limiter == "none"
    fct = smpm.StepOptions(transport="FMPM", transport_order=4, transport_limiter="fct")
    assert fct.transport_limiter == "fct" and "transport_limiter='fct'" in repr(fct)
    with pytest.raises(smpm.InputError, match=r"transport_limiter = fct: bounds FMPM\(k\) "
                                              r"transport without blending"):
        smpm.StepOptions(transport="lumped", transport_limiter="fct").validate()
    # [[material]] heat_capacity, conductivity, reference_temperature, thermal_expansion.
    mat = smpm.Material("m", heat_capacity=2.0, conductivity=0.5, reference_temperature=300.0,
                        thermal_expansion=1e-5)
    assert (mat.heat_capacity, mat.conductivity, mat.reference_temperature,
            mat.thermal_expansion) == (2.0, 0.5, 300.0, 1e-5)
    with pytest.raises(smpm.InputError, match="conductivity must be non-negative and finite"):
        smpm.Material(conductivity=-1.0)
    with pytest.raises(smpm.InputError, match="thermal_expansion is not for mie-gruneisen"):
        smpm.Material("g", "mie-gruneisen", bulk=1.0, thermal_expansion=1e-5)


def test_particle_temperatures_and_sources_are_views():
    bar = smpm.Model.from_toml(str(SOURCE / "examples" / "vibrating_bar.toml"))
    P = bar.particles
    # Without transport the particles carry neither (empty views).
    assert P.temperature.shape == (0,) and P.heat_source.shape == (0,)
    P.temperature = 310.0  # a number: every particle
    T = P.temperature
    assert T.shape == (80,) and np.all(T == 310.0)
    T[3] = 320.0  # writes the library's storage
    assert bar.particles.temperature[3] == 320.0
    P.temperature = np.linspace(300, 400, 80)  # copies into the same storage: T sees it
    assert T[-1] == 400.0
    P.heat_source = np.arange(80.0)
    assert np.array_equal(P.heat_source, np.arange(80.0))
    with pytest.raises(ValueError, match=r"expected a number or shape \(80,\), got \(79,\)"):
        P.temperature = np.full(79, 300.0)
    with pytest.raises(smpm.InputError, match="temperature: particle 2 has 0 .temperatures are "
                                              "absolute: positive and finite."):
        P.temperature = np.where(np.arange(80) == 2, 0.0, 300.0)
    assert T[2] > 0  # a refused assignment changes nothing
    # Model(..., temperature=, heat_source=) as [[body]] temperature and heat_source.
    model = smpm.Model(smpm.Grid([3]), X=[0.5, 1.5], mass=[1, 1], volume0=[1, 1],
                       materials=[smpm.Material()], temperature=[300.0, 350.0], heat_source=2.0)
    assert list(model.particles.temperature) == [300, 350] and list(model.particles.heat_source) == [2, 2]


def test_temperature_conditions_one_per_node():
    model = conduction_bar(cells=10)
    assert len(model.temperature_bcs) == 2 and model.temperature_bcs.num_constrained == 2
    # A node takes one temperature (they hold a value; they do not superpose as velocities do).
    with pytest.raises(smpm.InputError, match=r"node 1 is held by both 'add_bc\(temperature=400.0\)'"
                                              r" and 'add_bc\(temperature=500.0\)' \(a node takes "
                                              r"one temperature condition\)"):
        model.add_bc({"plane": {"axis": "x", "at": 0.0}, "temperature": 500.0})
    assert len(model.temperature_bcs) == 2  # the refused table was not added
    with pytest.raises(smpm.InputError, match="must be positive .temperatures are absolute."):
        model.add_bc({"plane": {"axis": "x", "at": 0.5}, "temperature": -5.0})
    with pytest.raises(smpm.InputError, match=r"a \[\[bc\]\] sets a temperature or velocities"):
        model.add_bc({"plane": {"axis": "x", "at": 0.5}, "temperature": 5.0, "fixed": ["x"]})
    assert len(model.bcs) == 0  # temperatures are not velocity conditions


@pytest.mark.parametrize("shape", SHAPES)
def test_capacity_matrices_are_the_scipy_products(blocks, shape):
    t = smpm.transport_operators(blocks, shape)
    ops = smpm.assemble(blocks, shape)
    P = blocks.particles
    n_g = t.grid_node_count
    assert ops.fields == 2 and t.S.shape == (len(P), n_g) and ops.num_nodes == 2 * n_g
    # The folded S is the step's S with column α n_g + i moved to i (each row has entries in one
    # field only, so the values are the same doubles).
    folded = scipy.sparse.csr_matrix((ops.S.data, ops.S.indices % n_g, ops.S.indptr), t.S.shape)
    assert (folded != t.S).nnz == 0
    # 𝗖 = M C_V and V κ = det(F) V⁰ κ per particle (one product each: exact).
    C_V, kappa = np.array([2.0, 0.5]), np.array([3.0, 1.0])
    assert np.array_equal(t.capacity, P.mass * C_V[P.material])
    assert np.array_equal(t.conductance, P.volume() * kappa[P.material])
    S, C = t.S, t.capacity
    # c = Sᵀ 𝗖 1 and c̃ = Sᵀ diag(𝗖) S: the same sums in another order (1e-13 of max c).
    c = S.T @ C
    assert np.abs(c - t.lumped_capacity).max() <= 1e-13 * c.max()
    ct = t.consistent_capacity()
    assert isinstance(ct, scipy.sparse.csr_matrix) and ct.shape == (n_g, n_g)
    assert abs(ct - S.T @ scipy.sparse.diags(C) @ S).max() <= 1e-13 * c.max()
    # Rows of c̃ sum to c (S 1 = 1), c̃ symmetric: round-off of max c.
    assert np.abs(np.asarray(ct.sum(axis=1)).ravel() - c).max() <= 1e-13 * c.max()
    assert abs(ct - ct.T).max() <= 1e-15 * c.max()
    # K = Σ_b G_bᵀ diag(V κ) G_b, symmetric, K 1 = 0 (Σ_i G_pi = 0): round-off of max |K|.
    K = t.conductivity_matrix()
    scale = abs(K).max()
    assert abs(K - sum(G.T @ scipy.sparse.diags(t.conductance) @ G for G in t.G)).max() <= 1e-13 * scale
    assert abs(K - K.T).max() <= 1e-15 * scale
    assert np.abs(K @ np.ones(n_g)).max() <= 1e-14 * scale
    # The kernels are these matrices: τ = Sᵀ(𝗖 T) and q = −K T + Sᵀ(M r) (round-off of the
    # terms' sizes: 𝗖 T and |K| |T|).
    tau = t.heat_content(P.temperature)
    assert np.abs(tau - S.T @ (C * P.temperature)).max() <= 1e-13 * tau.max()
    T = t.lumped_capacity_inv * tau
    q = t.heat_flow(T)
    assert np.abs(q - (-K @ T + S.T @ (P.mass * P.heat_source))).max() <= 1e-13 * (abs(K) @ T).max()
    assert np.array_equal(t.source, P.mass * P.heat_source)


def capacity_series(t, tau, k, alpha=1.0, every=1):
    """Σ_ℓ Δθ(ℓ) with Δθ(1) = c⁻¹ τ, Δθ(ℓ) = c_ℓ A_c Δθ(ℓ−1), A_c = I − c⁻¹ c̃ on the active
    nodes (zero rows elsewhere), c_ℓ = α when ℓ mod m = 1 (dense numpy)."""
    A = np.eye(t.grid_node_count) - t.lumped_capacity_inv[:, None] * t.consistent_capacity().toarray()
    A[~t.active] = 0
    d = t.lumped_capacity_inv * tau
    total = d.copy()
    for ell in range(2, k + 1):
        d = (alpha if every == 1 or ell % every == 1 else 1.0) * (A @ d)
        total += d
    return total, A


@pytest.mark.parametrize("k", [1, 2, 3, 5, 8])
def test_fmpm_temperature_is_the_capacity_series(blocks, k):
    t = smpm.transport_operators(blocks, "gimp")
    tau = t.heat_content(blocks.particles.temperature)
    ref, _ = capacity_series(t, tau, k)
    theta = smpm.fmpm_temperature(t, tau, k)
    # θ(k) = Σ_{j<k} A_cʲ c⁻¹ τ: temperatures of size 300, round-off of k products.
    assert theta.shape == tau.shape and np.abs(theta - ref).max() <= 1e-13 * k * 300
    if k > 1:  # the series changes θ: the check cannot pass by returning c⁻¹ τ
        assert np.abs(ref - t.lumped_capacity_inv * tau).max() > 1e-3
    blended, _ = capacity_series(t, tau, k, alpha=0.8, every=2)
    got = smpm.fmpm_temperature(t, tau, k, blend_alpha=0.8, blend_every=2)
    assert np.abs(got - blended).max() <= 1e-13 * k * 300


def test_fmpm_temperature_tends_to_the_exact_inverse(blocks):
    t = smpm.transport_operators(blocks, "gimp", "exact")
    tau = t.heat_content(blocks.particles.temperature)
    act = t.active
    c = t.lumped_capacity[act]
    ct = t.consistent_capacity().toarray()[np.ix_(act, act)]
    exact = smpm.exact_temperature(t, tau)
    # CHOLMOD solves c̃ θ = τ on the active nodes: against LAPACK to round-off of cond(c̃) ~ 1e2
    # times temperatures of 300; zero elsewhere.
    assert np.abs(exact[act] - scipy.linalg.solve(ct, tau[act], assume_a="pos")).max() <= 1e-11
    assert np.all(exact[~act] == 0)
    # A_c = I − c⁻¹ c̃ is similar to a symmetric matrix: |A_cʲ x| ≤ √(c_max/c_min) ρʲ |x|, so
    # |θ(k) − θ| ≤ √(c_max/c_min) ρᵏ/(1 − ρ) |c⁻¹ τ| (FMPM 2026 §2.2 with c for m), plus round-off.
    _, A = capacity_series(t, tau, 1)
    rho = np.abs(scipy.linalg.eigvals(A[np.ix_(act, act)])).max()
    assert 0.5 < rho < 1
    start = np.linalg.norm(tau[act] / c)
    errors = []
    for k in (1, 4, 16, 64, 256):
        err = np.linalg.norm(smpm.fmpm_temperature(t, tau, k)[act] - exact[act])
        bound = np.sqrt(c.max() / c.min()) * rho**k / (1 - rho) * start
        assert err <= bound + 1e-12 * np.linalg.norm(exact), (k, err, bound)
        errors.append(err)
    assert all(b < a for a, b in zip(errors, errors[1:]))  # it approaches θ = c̃⁻¹ τ ...
    assert errors[-1] < 1e-5 * np.linalg.norm(exact)  # ... and reaches it (ρ²⁵⁶ ≈ 6e-8)


def test_conditions_hold_the_nodal_temperature():
    # With the temperature conditions (the step's: transport.temperature_bcs) the held nodes
    # take their temperature, for FMPM(k) (τ_i = c_i T_b, increments zeroed: round-off of
    # c_i T_b / c_i) and the exact solve, whose other nodes solve c̃_ff θ_f = τ_f − c̃_fh θ_h
    # (LAPACK against CHOLMOD: round-off of temperatures of 400).
    model = conduction_bar(cells=10)
    t = smpm.transport_operators(model)
    tau = t.heat_content(model.particles.temperature)
    x = t.grid.node_positions()[:, 0]
    held = np.isclose(x, 0.0) | np.isclose(x, 1.0)
    values = np.array([400.0, 350.0])
    for theta in (smpm.fmpm_temperature(t, tau, 4, bcs=t.temperature_bcs),
                  smpm.exact_temperature(t, tau, bcs=t.temperature_bcs)):
        assert np.abs(theta[held] - values).max() <= 1e-13 * 400
    free = t.active & ~held
    ct = t.consistent_capacity().toarray()
    ref = scipy.linalg.solve(ct[np.ix_(free, free)], tau[free] - ct[np.ix_(free, held)] @ values)
    assert np.abs(theta[free] - ref).max() <= 1e-11
    assert np.abs(theta[free] - 300).max() > 1  # the held ends pull their neighbours


def test_conduction_bar_follows_the_series_solution():
    # T0 = 300, ends held at 400 and 350, D = L = 1, t = 0.05; FMPM(4), linear shapes, 2
    # particles per cell, 40 cells, F = DΔt/Δx² = 0.1 (advance's conduction limit with
    # fourier=0.1: 800 steps). The C++ test measured a largest particle error of 0.0136 K
    # (second order in Δx): asserted < 0.03 K.
    T0, T1, T2, end = 300.0, 400.0, 350.0, 0.05
    model = conduction_bar(40, T0, T1, T2)
    assert smpm.diffusion_time(model) == pytest.approx(1 / 40**2, rel=1e-15)
    stepper = smpm.Stepper(model.options)
    report = stepper.advance(model, end=end, fourier=0.1)
    assert report.steps == 800 and model.time == pytest.approx(end, rel=1e-14)
    P = model.particles
    assert np.abs(P.temperature - series(P.X[:, 0], end, T0, T1, T2)).max() < 0.03
    # The nodal temperatures θ⁺ of the last step, rows on the grid nodes `nodes`: the held ends
    # exactly, the others within 0.1 K of the series (measured 0.046 K, second order).
    s = stepper.transport_state
    x = model.grid.node_positions()[s.nodes, 0]
    inside = (x > -1e-12) & (x < 1 + 1e-12)
    assert s.theta[inside][0] == T1 and s.theta[inside][-1] == T2
    assert np.abs(s.theta[inside] - series(x[inside], end, T0, T1, T2)).max() < 0.1
    assert s.tau.shape == s.T.shape == s.q.shape == (len(s.nodes),) and s.gradient.shape == (80, 1)
    # The thermal sums against their definitions (round-off of sums of 80 terms of size 300 h).
    ts = smpm.thermal_sums(model)
    C = P.mass  # C_V = 1
    assert ts.temperature_min == P.temperature.min() and ts.temperature_max == P.temperature.max()
    assert ts.temperature_mean == pytest.approx((C * P.temperature).sum() / C.sum(), rel=1e-14)
    assert ts.heat == pytest.approx((C * (P.temperature - T0)).sum(), rel=1e-13)
    entropy = (C * np.log(P.temperature / T0)).sum()
    assert ts.entropy == pytest.approx(entropy, rel=1e-13)
    assert ts.internal == pytest.approx(ts.heat, rel=1e-13)  # W = 0: the bar is at rest
    assert ts.helmholtz == pytest.approx(ts.internal - (P.temperature * C * np.log(P.temperature / T0)).sum(),
                                         rel=1e-12)
    # An isothermal stepper has no transport state.
    assert smpm.Stepper(smpm.StepOptions()).transport_state is None


def test_heated_run_equals_smpm_run_bit_for_bit(heated_bar, tmp_path):
    # The same library calls in the same order: identical temperatures and thermal series (every
    # row: the first from model.energies(), the others from the energies advance's callback gets).
    out = tmp_path / "heated.h5"
    r = run_smpm("run", heated_bar, "-q", "-o", out)
    assert r.returncode == 0, r.stderr
    model = smpm.Model.from_toml(str(heated_bar))
    assert model.fourier == 0.2 and model.options.transport == "FMPM"
    rows = [smpm.thermal_sums(model)]
    report = smpm.Stepper(model.options).advance(
        model, callback=lambda m, e, at_stop: rows.append(smpm.thermal_sums(m, e.strain)),
        stop_every=10.0)
    assert report.steps == 400  # the conduction limit of [time] fourier (see HEATED_BAR)
    with h5py.File(out, "r") as f:
        frame = f["particles"]["000002"]
        assert frame.attrs["time"] == 20.0
        for name in ("temperature", "X", "V", "stress"):
            assert np.array_equal(getattr(model.particles, name), frame[name][...]), name
        for name in ("temperature_min", "temperature_max", "temperature_mean", "heat", "internal",
                     "entropy", "helmholtz"):
            assert np.array_equal([getattr(row, name) for row in rows], f["series"][name][...]), name
    assert model.particles.temperature.max() > 350  # it was heated (source and held end)


def test_every_heat_table_of_an_input_from_python(heated_bar):
    # The heated bar rebuilt from arrays: [[material]] as Material(**keys), [[body]] temperature
    # and heat_source as Model(temperature=, heat_source=), [[bc]] temperature through add_bc,
    # [step] as StepOptions(**keys): 100 steps equal the input's bit for bit.
    tables = tomllib.loads(HEATED_BAR)
    ref = smpm.Model.from_toml(str(heated_bar))
    P = ref.particles
    materials = [smpm.Material(t["name"], t["model"], **{k: v for k, v in t.items()
                                                         if k not in ("name", "model")})
                 for t in tables["material"]]
    model = smpm.Model(ref.grid, P.X, P.mass, P.volume0, V=P.V, material=P.material,
                       materials=materials, half_length=P.half_length, temperature=P.temperature,
                       heat_source=P.heat_source)
    for bc in tables["bc"]:
        model.add_bc(bc)
    assert len(model.temperature_bcs) == len(ref.temperature_bcs) == 1
    options = smpm.StepOptions(**tables["step"])
    assert repr(options) == repr(ref.options)
    for m, o in ((ref, ref.options), (model, options)):
        stepper = smpm.Stepper(o)
        for _ in range(100):
            stepper.step(m, 0.05)
    for name in ("X", "V", "F", "stress", "temperature"):
        assert np.array_equal(getattr(model.particles, name), getattr(ref.particles, name)), name


def test_errors_of_heat_transport():
    bare = smpm.Model(smpm.Grid([3]), X=[0.5, 1.5], mass=[1, 1], volume0=[1, 1],
                      materials=[smpm.Material()])
    # A material without a heat capacity cannot carry heat: the library's message.
    with pytest.raises(smpm.InputError, match="material 'material': heat transport needs "
                                              "heat_capacity > 0"):
        smpm.transport_operators(bare)
    with pytest.raises(smpm.InputError, match="transport 'off' has no operators"):
        smpm.transport_operators(conduction_bar(10), transport="off")
    with pytest.raises(smpm.UsageError, match="the particles have no temperatures"):
        smpm.thermal_sums(bare)
    t = smpm.transport_operators(conduction_bar(10))
    with pytest.raises(ValueError, match="tau: expected 13 rows"):
        smpm.fmpm_temperature(t, np.ones(12), 2)
    with pytest.raises(smpm.InputError, match="order = 0"):
        smpm.fmpm_temperature(t, np.ones(13), 0)


def test_critical_fourier_matches_the_command(tmp_path):
    # F* of the conduction bar at its input's lattice (--shifts 1): critical_fourier from Python
    # gives the critical_fourier column of `smpm transport-stability` (4 digits), for the lumped
    # update, FMPM(2) on c~ and the exact solve; a CriticalFourier with rho_T and the counts.
    bar = smpm.Model.from_toml(str(SOURCE / "examples" / "conduction_bar.toml"))
    out = tmp_path / "transport.csv"
    r = run_smpm("transport-stability", SOURCE / "examples" / "conduction_bar.toml", "--order", "2",
                 "--shifts", "1", "-o", out)
    assert r.returncode == 0, r.stderr
    table = {(row["transport"], row["order"]): row for row in smpm.read_table(out)}
    for transport, order in (("lumped", ""), ("FMPM", "2"), ("exact", "")):
        o = bar.options.copy()
        o.transport = transport
        o.transport_order = int(order or 1)
        f = smpm.critical_fourier(bar, o)
        assert isinstance(f, smpm.CriticalFourier) and float(f) == f.critical_fourier
        row = table[transport, order]
        assert f"{f.critical_fourier:.4g}" == row["critical_fourier"]
        assert f"{f.rho_T:.10g}" == row["rho_T"] and f.evaluations == int(row["evaluations"])
        assert f.rho_T <= 1 + 1e-6 and f.non_finite == 0
        # what lies below F*: the conduction bar is stable to F -> 0
        assert f.small == "stable" and f.small_fourier == row["small_fourier"] == "stable to 0"
    with pytest.raises(smpm.InputError):
        o = bar.options.copy()
        o.transport = "off"
        smpm.critical_fourier(bar, o)
    # The FCT limiter is not linear: the linearised transport step refuses it.
    o = bar.options.copy()
    o.transport, o.transport_order, o.transport_limiter = "FMPM", 2, "fct"
    with pytest.raises(smpm.InputError, match="is not linear"):
        smpm.critical_fourier(bar, o)
