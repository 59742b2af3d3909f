"""Bad input gets a clear error naming the problem and what was expected."""

from __future__ import annotations

import threading

import numpy as np
import pytest

import cgadyn

PANDA = cgadyn.load("panda")
Z9 = np.zeros(9)


def test_wrong_length_names_n_and_the_joint_order():
    with pytest.raises(ValueError, match=r"shape \(9,\).*panda_joint1, panda_joint2"):
        cgadyn.rnea(PANDA, np.zeros(7), Z9, Z9)
    with pytest.raises(ValueError, match="tau must have shape"):
        cgadyn.aba(PANDA, Z9, Z9, np.zeros((3, 8)))
    with pytest.raises(ValueError, match="batches of the same size"):
        cgadyn.rnea(PANDA, np.zeros((2, 9)), np.zeros((3, 9)), np.zeros((3, 9)))


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_input_names_array_and_joint(bad):
    v = Z9.copy()
    v[4] = bad
    with pytest.raises(ValueError, match=r"v contains NaN or inf at index \(4,\).*panda_joint5"):
        cgadyn.rnea(PANDA, Z9, v, Z9)
    with pytest.raises(ValueError, match="v contains NaN or inf"):
        cgadyn.aba(PANDA, Z9, v, Z9)
    with pytest.raises(ValueError, match="q contains NaN or inf"):
        cgadyn.crba(PANDA, v)
    with pytest.raises(ValueError, match="NaN or inf"):
        cgadyn.aba(PANDA, np.zeros((2, 9)), np.stack([Z9, v]), np.zeros((2, 9)))


def test_bad_gravity_and_f_ext():
    with pytest.raises(ValueError, match="gravity must be 3 finite numbers"):
        cgadyn.rnea(PANDA, Z9, Z9, Z9, gravity=(0, 0))
    with pytest.raises(ValueError, match=r"f_ext must have shape \(9, 6\)"):
        cgadyn.rnea(PANDA, Z9, Z9, Z9, f_ext=np.zeros((9, 3)))


def test_unknown_robot_lists_known_names():
    with pytest.raises(ValueError, match="panda.*ur5|ur5.*panda"):
        cgadyn.load("no_such_robot")


def test_missing_file_and_malformed_xml(tmp_path):
    with pytest.raises(FileNotFoundError):
        cgadyn.load(tmp_path / "missing.urdf")
    bad = tmp_path / "bad.urdf"
    bad.write_text("<robot name='x'><link name='a'></robot>")
    with pytest.raises(ValueError, match="(?i)xml|malformed"):
        cgadyn.load(bad)


def _urdf(joint_type: str, child_inertial: bool = True) -> str:
    inertial = (
        "<inertial><mass value='1'/><inertia ixx='0.1' iyy='0.1' izz='0.1' ixy='0' ixz='0'"
        " iyz='0'/></inertial>"
        if child_inertial
        else ""
    )
    return f"""<robot name="t">
      <link name="base"/>
      <link name="arm">{inertial}</link>
      <joint name="j1" type="{joint_type}"><parent link="base"/><child link="arm"/>
        <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
    </robot>"""


@pytest.mark.parametrize("kind", ["floating", "planar"])
def test_unsupported_joint_type_is_named(kind):
    with pytest.raises(ValueError, match=f"j1.*{kind}|{kind}.*j1"):
        cgadyn.load(_urdf(kind))


def test_massless_movable_subtree_names_the_joint():
    model = cgadyn.load(_urdf("revolute", child_inertial=False))
    with pytest.raises(ValueError, match="singular articulated-body inertia.*j1"):
        cgadyn.aba(model, np.zeros(1), np.zeros(1), np.ones(1))


def test_two_threads_share_a_model():
    """Concurrent calls on one model each use their own workspace."""
    rng = np.random.default_rng(0)
    q, v, tau = (rng.uniform(-1, 1, (64, 9)) for _ in range(3))
    expected = np.array([cgadyn.aba(PANDA, q[i], v[i], tau[i]) for i in range(64)])
    results: dict[int, np.ndarray] = {}

    def work(k: int) -> None:
        out = np.empty((64, 9))
        for _ in range(20):
            for i in range(64):
                out[i] = cgadyn.aba(PANDA, q[i], v[i], tau[i])
        results[k] = out

    threads = [threading.Thread(target=work, args=(k,)) for k in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for k in range(2):
        np.testing.assert_array_equal(results[k], expected)


@pytest.mark.parametrize("bad, message", [
    (None, "q is None; expected an array of shape"),
    (1.5, r"shape \(9,\) or \(B, 9\).*got \(\)"),
    (np.zeros(9, dtype=complex), "complex values; expected real numbers"),
    (["a"] * 9, "real numbers"),
])
def test_states_that_are_not_real_arrays_are_refused(bad, message):
    for call in (lambda: cgadyn.rnea(PANDA, bad, Z9, Z9), lambda: cgadyn.crba(PANDA, bad),
                 lambda: cgadyn.aba(PANDA, bad, Z9, Z9)):
        with pytest.raises(ValueError, match=message):
            call()


def test_jacobian_link_must_be_a_name_or_an_integer():
    with pytest.raises(ValueError, match="link must be a link name or an integer index"):
        cgadyn.jacobian(PANDA, Z9, 2.7)
    with pytest.raises(ValueError, match="out of range"):
        cgadyn.jacobian(PANDA, Z9, 99)
    np.testing.assert_array_equal(cgadyn.jacobian(PANDA, Z9, np.int64(3)),
                                  cgadyn.jacobian(PANDA, Z9, PANDA.link_names[3]))


def test_f_ext_shape_message_names_both_forms():
    with pytest.raises(ValueError, match=r"f_ext must have shape \(9, 6\) or \(2, 9, 6\)"):
        cgadyn.rnea(PANDA, np.zeros((2, 9)), np.zeros((2, 9)), np.zeros((2, 9)),
                    f_ext=np.zeros((3, 6)))
    with pytest.raises(ValueError, match=r"f_ext must have shape \(9, 6\) \(one"):
        cgadyn.rnea(PANDA, Z9, Z9, Z9, f_ext=np.zeros((3, 6)))
