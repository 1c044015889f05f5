"""The KXR-L2W2L6A4H2 as kxreus weighs and assembles it: per-link masses and centres of mass
where the source weighs each link of a build, the ankle wheel and the A4 arm offsets; the
figures are kxreus's, repeated here as the numbers a reader checks against
``kxrl2w2l6a4h2.json`` (physics.links and the link headers)."""

from __future__ import annotations

import pytest

from rcb4hv.robot.kit import kit_model
from rcb4hv.robot.kit.assembly import assemble
from rcb4hv.robot.kit.build import stock_joint_map
from rcb4hv.robot.kit.figures import LEG_SLOTS, MASS_SERVOS, LinkFigure, fig, link_figures
from rcb4hv.robot.kit.templates import template
from tests.robot.kit_names import names_for, stock


def test_the_wheel_leg_build_weighs_its_links_as_kxreus_does() -> None:
    _, model = stock("kxr:L2W2L6A4H2G")
    ankle = model.link("l_ankle_pitch_link").inertial
    # three servos (ankle pitch, roll, wheel), each brought from kxreus's 27.73 g to 35.03 g
    servo = (fig("servo.mass") - fig("servo.mass_kxreus")) / 1000
    assert ankle.mass == pytest.approx(0.122858 + 3 * servo)
    assert ankle.com == pytest.approx((-0.033808, 0.0, 0.009676))  # behind the ankle
    # its moments about the pitch and yaw axes: a long link (the wheel servo 78 mm back)
    assert ankle.inertia[:3] == pytest.approx((2.072716e-05, 1.4003496e-04, 1.3574437e-04))
    right = model.link("r_ankle_pitch_link").inertial
    assert right.mass == pytest.approx(ankle.mass) and right.com[1] == pytest.approx(0.0)
    assert model.link("l_ankle_wheel_link").inertial.mass == pytest.approx(0.040332)
    assert model.link("r_ankle_wheel_link").inertial.com[1] == pytest.approx(-0.023412)
    torso = model.link("torso").inertial
    assert torso.mass == pytest.approx(0.437985 + 5 * servo)
    assert torso.com == pytest.approx((-0.006626, 0.0, 0.030964))
    # kxreus's head link carries its 145.7 g Euclid head; Kondo's build does not
    assert model.link("neck_pitch_link").inertial.mass == pytest.approx(0.010821)
    # kxreus's total less the tyre it puts on each A4 arm (no servo for it in Kondo's project)
    # and the Euclid head, its 26 servo cases at 35.03 g
    total = fig("mass.L2W2L6A4H2G") - 2 * fig("wheel.tyre_mass") - fig("part.euclid_head")
    assert total == pytest.approx(1652.61, abs=0.01)
    assert model.mass == pytest.approx(total / 1000 + 26 * servo, abs=1e-5)
    # the legs carry about 45 % of it (the volume sharing put about half there)
    legs = sum(
        link.inertial.mass
        for link in model.links
        if any(k in link.name for k in ("hip", "knee", "ankle"))
    )
    assert legs / model.mass == pytest.approx(0.45, abs=0.01)


def test_the_ankle_wheel_turns_behind_the_ankle_where_kxreus_puts_it() -> None:
    _, model = stock("kxr:L2W2L6A4H2G")
    wheel = model.joint("l_ankle_wheel")
    assert wheel.parent == "l_ankle_pitch_link"
    assert wheel.xyz == pytest.approx((-0.07803, 0.0, 0.0))  # lleg-ankle-w pos
    (tyre,) = model.link("r_ankle_wheel_link").geoms
    assert tyre.pos == pytest.approx((0.0, -0.0235, 0.0))  # outboard of the right leg


def test_a_detected_project_gets_the_same_masses() -> None:
    from rcb4hv.robot.kit import detect_kit

    _, model = stock("kxr:L2W2L6A4H2G")
    det = detect_kit("Hello_KXR-L2W2L6A4H2", names_for(model))
    assert det.model.name == "kxr:L2W2L6A4H2G"
    assert det.model.mass == pytest.approx(model.mass)
    hip = 0.078374 + 2 * (fig("servo.mass") - fig("servo.mass_kxreus")) / 1000  # 2 cases
    assert det.model.link("l_hip_roll_link").inertial.mass == pytest.approx(hip)


def test_builds_without_per_link_figures_share_their_total() -> None:
    """kxreus's total with each of the build's 30 servos at a KRS-3304R2's mass, not the
    27.73 g kxreus weighs every servo case at (KXR-KITS.md §3.1)."""
    assert link_figures("L2L6A7H2G") == {}
    _, model = stock("kxr:L2L6A7H2G")
    short = fig("servo.mass") - fig("servo.mass_kxreus")
    assert len(model.servos) == 30
    assert model.mass == pytest.approx((fig("mass.L2L6A7H2G") + 30 * short) / 1000)


@pytest.mark.parametrize(
    ("code", "weighed", "cases"),
    [("kxr:L2L6A7H2G", "L2L6A6H2G", 5), ("kxr:L2L5A3H2G", "L2W2L5A3H2G", 3)],
)
def test_an_unweighed_humanoid_has_the_weighed_torso_less_its_servo_cases(
    code: str, weighed: str, cases: int
) -> None:
    """One KXR humanoid torso (board, battery box, back pack, frames) in every build: a build
    kxreus does not weigh link by link takes the weighed build's torso with the same legs,
    less the servo cases on it (those servos weigh in with their joints' links), and keeps its
    own total. The weighed torsos agree on their contents within 10 g."""
    _, model = stock(code)
    source = link_figures(weighed)["torso"]
    torso = model.link("torso").inertial
    assert torso.mass == pytest.approx((source.mass - cases * fig("servo.mass")) / 1000)
    assert torso.com == pytest.approx(tuple(c / 1000 for c in source.com))
    contents = [
        link_figures(b)["torso"].mass - fig(f"lcases.{b}.torso") * fig("servo.mass")
        for b in ("L2W2L5A3H2G", "L2L6A6H2G", "L2W2L6A4H2G")
    ]
    assert max(contents) - min(contents) < 10.0
    # and the build's own total stays (test_builds_without_per_link_figures_share_their_total)


@pytest.mark.parametrize(
    ("code", "weighed", "slots"),
    [
        ("kxr:L2L6A7H2G", "L2L6A6H2G", LEG_SLOTS),
        ("kxr:L2L5A3H2G", "L2L6A6H2G", LEG_SLOTS[1:]),
        ("kxr:L2W2L6A5H2G", "L2W2L6A4H2G", (*LEG_SLOTS, "ankle_wheel")),
        ("kxr:L2W2L5A4H2G", "L2W2L5A3H2G", (*LEG_SLOTS[1:], "ankle_wheel")),
    ],
)
def test_an_unweighed_humanoid_has_the_weighed_legs(
    code: str, weighed: str, slots: tuple[str, ...]
) -> None:
    """The same leg parts weigh the same in every build: a build no source weighs link by
    link takes each leg link's mass, centre and moments from the weighed build with the same
    legs (the five-axis leg is the six-axis one below its hip yaw; kxrl2g.l's five-axis leg
    links are those, their cases at 27.73 g). The hip yaw link carries its servo's case,
    which the weighed build counts in its torso."""
    _, model = stock(code)
    source = link_figures(weighed)
    for slot in slots:
        link = model.link(f"l_{slot}_link").inertial
        extra = fig("servo.mass") if slot == "hip_yaw" else 0.0
        assert link.mass == pytest.approx((source[slot].mass + extra) / 1000), slot
        if source[slot].com is not None:
            com = source[slot].com
            assert link.com == pytest.approx((com[0] / 1000, com[1] / 1000, com[2] / 1000))
    # kxrl2g.l's five-axis leg (kxr.py), each case brought to a KRS-3304R2's mass
    short = fig("servo.mass") - fig("servo.mass_kxreus")
    five = {"hip_roll": 78.374 + 2 * short, "hip_pitch": 22.434, "knee_pitch": 54.3 + short}
    for slot, grams in five.items():
        assert link_figures("L2L6A6H2G")[slot].mass == pytest.approx(grams, abs=0.1), slot


A3 = ("shoulder_pitch", "shoulder_roll", "elbow_pitch", "gripper")
A4 = ("shoulder_pitch", "shoulder_roll", "shoulder_yaw", "elbow_pitch")  # its gripper: unweighed
A6 = (*A4, "wrist_pitch", "wrist_roll", "gripper")


@pytest.mark.parametrize(
    ("code", "weighed", "slots"),
    [
        ("kxr:L2L5A3G", "L2W2L5A3H2G", A3),
        ("kxr:L2L5A3H2G", "L2W2L5A3H2G", A3),
        ("kxr:L2L6A4H2G", "L2W2L6A4H2G", A4),
        ("kxr:L2W2L5A4H2G", "L2W2L6A4H2G", A4),
        ("kxr:L2L5A6H2G", "L2L6A6H2G", A6),
        ("kxr:L2W2L6A6H2G", "L2L6A6H2G", A6),
        ("kxr:L2L6A6G", "L2L6A6H2G", A6),
    ],
)
def test_an_unweighed_humanoid_has_the_weighed_arms(
    code: str, weighed: str, slots: tuple[str, ...]
) -> None:
    """The arm links of a build no source weighs link by link are those of the weighed build
    whose arm has the same joints (the A6 arm weighed 253.8 g a side in the KXR-L2W2L6A6H2G,
    servos and a share of the total, against 347.0 g in the KXR-L2L6A6H2G). The shoulder
    pitch link carries its servo's case, which the weighed build counts in its torso."""
    _, model = stock(code)
    source = link_figures(weighed)
    for slot in slots:
        link = model.link(f"l_{slot}_link").inertial
        extra = fig("servo.mass") if slot == "shoulder_pitch" else 0.0
        assert link.mass == pytest.approx((source[slot].mass + extra) / 1000), slot


def test_an_arm_no_build_weighs_shares_the_total() -> None:
    """A5 and A7 arms, and an A3 arm without its gripper (whose elbow link carries a case
    fewer), take no weighed arm: they share what the build's total leaves."""
    weighed_a6 = link_figures("L2L6A6H2G")["elbow_pitch"].mass / 1000
    for code in ("kxr:L2L6A7H2G", "kxr:L2L6A5H2G", "kxr:L2L5A3"):
        _, model = stock(code)
        assert model.link("l_elbow_pitch_link").inertial.mass != pytest.approx(weighed_a6), code


def test_a_build_with_more_parts_weighs_more() -> None:
    """Two ankle wheels on the same build add their servos and tyres; a head adds its own
    (a sweep found the 30-servo KXR-L2W2L6A6H2G 137 g lighter than the 28-servo
    KXR-L2L6A6H2G when only the legs and torso were the weighed builds')."""
    mass = {c: stock(c)[1].mass for c in ("kxr:L2L6A6H2G", "kxr:L2W2L6A6H2G", "kxr:L2L6A6G")}
    wheels = 2 * (fig("servo.mass") + link_figures("L2W2L6A4H2G")["ankle_wheel"].mass) / 1000
    assert mass["kxr:L2W2L6A6H2G"] > mass["kxr:L2L6A6H2G"] + wheels * 0.5
    assert mass["kxr:L2L6A6G"] < mass["kxr:L2L6A6H2G"]


@pytest.mark.parametrize(("code", "family"), [("kxr:L4T", "L4T"), ("kxr:L6", "L6")])
def test_family_totals_count_their_servos_at_the_krs_3304r2s_mass(code: str, family: str) -> None:
    _, model = stock(code)
    short = fig("servo.mass") - fig("servo.mass_kxreus")
    servos = MASS_SERVOS[family]
    assert len(model.servos) == servos  # the family's reference build itself
    assert model.mass == pytest.approx((fig(f"mass.{family}") + servos * short) / 1000)


def test_the_a6_build_weighs_its_links_as_kxreus_does() -> None:
    # kxrl2l6a6h2.json physics.links: 31 links summing to its total, 1708.46 g, with its 28
    # servo cases at 35.03 g (kxreus's 27.73 g)
    _, model = stock("kxr:L2L6A6H2G")
    servo = (fig("servo.mass") - fig("servo.mass_kxreus")) / 1000
    assert model.mass == pytest.approx(fig("mass.L2L6A6H2G") / 1000 + 28 * servo, abs=1e-5)
    assert model.link("torso").inertial.com == pytest.approx((-0.006705, 0.0, 0.030964))
    assert model.link("l_wrist_pitch_link").inertial.mass == pytest.approx(0.078374 + 2 * servo)
    # the two fingers as one link: 26.534 g, 20 mm forward of the gripper joint
    grip = model.link("r_gripper_link").inertial
    assert grip.mass == pytest.approx(0.026534) and grip.com[0] == pytest.approx(0.020023)
    assert model.link("r_ankle_roll_link").inertial.com[1] == pytest.approx(-0.007514)


def test_parts_a_weighed_build_lacks_weigh_their_servo_and_tyre() -> None:
    # a kxra6g-style A6 biped with base wheels: kxreus weighs the A6 build without them
    _, plain = stock("kxr:L2L6A6H2G")
    code, _ = stock("kxr:L2L6A6H2G")
    jm = stock_joint_map(code)
    jm.update({"r_front_wheel": (0, 1), "l_front_wheel": (1, -1)})
    wheeled = kit_model(code, jm)
    tyre = fig("wheel.tyre_mass") + fig("mass.per_servo")
    assert wheeled.link("l_front_wheel_link").inertial.mass == pytest.approx(tyre / 1000)
    assert wheeled.mass == pytest.approx(plain.mass + 2 * tyre / 1000)


def test_links_without_a_figure_share_what_is_left() -> None:
    code, _ = stock("kxr:L2L6A6H2G")
    jm = stock_joint_map(code)
    bases = sorted({j[2:] if j[:2] in ("l_", "r_") else j for j in jm})
    model = assemble(
        template(code),
        bases,
        jm,
        name="x",
        title="x",
        sources={},
        total_mass=1.7,
        link_masses={
            "torso": LinkFigure(500.0, (0.0, 0.0, 30.0), (5000.0, 4000.0, 3000.0)),
            "hip_roll": LinkFigure(80.0, None, None),
        },
    )
    assert model.mass == pytest.approx(1.7)
    assert model.link("torso").inertial.mass == pytest.approx(0.5)
    assert model.link("torso").inertial.com == pytest.approx((0.0, 0.0, 0.03))
    assert model.link("torso").inertial.inertia == pytest.approx((5e-4, 4e-4, 3e-4, 0, 0, 0))
    assert model.link("r_hip_roll_link").inertial.mass == pytest.approx(0.08)


def test_the_a4_arm_has_kxreus_a4_offsets() -> None:
    # kxrl2w2l6a4h2.json: shoulder-r 29 mm out, shoulder-y 67 mm below it, elbow 29 mm
    # below that, gripper 65.5 mm below the elbow (not the A6 arm's 15 + 41 mm)
    _, model = stock("kxr:L2W2L6A4H2G")
    assert model.joint("l_shoulder_roll").xyz == pytest.approx((0.0, 0.029, 0.0))
    assert model.joint("l_shoulder_yaw").xyz == pytest.approx((0.0, 0.0, -0.067))
    assert model.joint("l_elbow_pitch").xyz == pytest.approx((0.0, 0.0, -0.029))
    assert model.joint("r_gripper").xyz == pytest.approx((0.0, 0.0, -0.0655))
    _, a6 = stock("kxr:L2L6A6H2G")
    assert a6.joint("l_shoulder_yaw").xyz == pytest.approx((0.0, 0.0, -0.015))


@pytest.mark.parametrize(
    ("code", "left_out", "cases"),
    [
        # the tyres kxreus puts on the A4 arms' ends, and its Euclid head (145.7 g)
        ("kxr:L2W2L6A4H2G", 2 * 39.87 + 145.7, 26),
        ("kxr:L2L6A6H2G", 0.0, 28),
        ("kxr:L2W2L5A3H2G", 2 * 39.87 + 145.7, 22),  # the tyres on the grippers, the head
    ],
)
def test_weighed_builds_weigh_kxreus_totals_less_what_kondo_lacks(
    code: str, left_out: float, cases: int
) -> None:
    # every link of these builds has a row; the model's mass is their sum: kxreus's total
    # less the parts without a servo in Kondo's projects, its servo cases at 35.03 g
    _, model = stock(code)
    total = fig("mass." + code.split(":")[1])
    servo = fig("servo.mass") - fig("servo.mass_kxreus")
    assert model.mass * 1000 == pytest.approx(total - left_out + cases * servo, abs=0.01)


def test_the_l2gh_leaves_out_the_eyes_kxreus_s_head_carries() -> None:
    # kxreus's KXR-L2L5A3H2G (kxrl2l5a3h2g.json) has a head with two eye servos and two eye
    # links; Kondo's KXR-L2GH has none, so its total leaves them out (its 20 servo cases at
    # 35.03 g)
    _, model = stock("kxr:L2L5A3H2G")
    left_out = fig("leftout.L2L5A3H2G")
    assert left_out == pytest.approx(2 * 27.73 + 2 * 43.241)
    servo = fig("servo.mass") - fig("servo.mass_kxreus")
    expected = fig("mass.L2L5A3H2G") - left_out + 20 * servo
    assert model.mass * 1000 == pytest.approx(expected, abs=0.01)


def test_the_humanoid_reference_total_is_the_twenty_servo_build() -> None:
    # the family's reference (20 servos) is kxrl2l5a3h2g.json's build, whose total counts two
    # eye servos and eye links more: the reference leaves them out, as the L2GH's model does
    reference = fig("mass.humanoid")
    assert reference == pytest.approx(fig("mass.L2L5A3H2G") - fig("leftout.L2L5A3H2G"))
    assert MASS_SERVOS["humanoid"] == 20
    _, l2gh = stock("kxr:L2L5A3H2G")  # 20 servos: the reference at a KRS-3304R2's mass
    servo = fig("servo.mass") - fig("servo.mass_kxreus")
    assert l2gh.mass * 1000 == pytest.approx(reference + 20 * servo, abs=0.01)
