"""Names of the MJCF elements: the model writes them from here and Python reads
them from here (one place, no scattered strings). Per-side tuples are in
``SIDES`` order."""

BODY = "body"  #: the thorax/abdomen; its frame origin is the body centre
HEAD = "head"
ROOT_JOINT = "root"  #: the free joint of the body
FLOOR = "floor"
DEBRIS = "debris"  # prefix of the debris scene's boxes: debris0, debris1, ...
WALL = "wall"  # prefix of the walls around a debris field: wall0 ... wall3
READY_KEY = "ready"  #: keyframe of the settled start state (Fig. 4)

SIDES = ("l", "r")  #: left (+y) and right (-y)

#: Passive fore and middle legs: a geom, or with sprung struts a body, hinge
#: and geom, all of this name.
FORE_LEGS = ("fore_l", "fore_r")
MID_LEGS = ("mid_l", "mid_r")

# Hind legs: body–femur ("hip") and femur–tibia ("knee") hinges, both actuated.
HIP_JOINTS = ("hip_l", "hip_r")
KNEE_JOINTS = ("knee_l", "knee_r")
#: The four actuated joints in the paper's input order I1–I4.
ACTUATED_JOINTS = (HIP_JOINTS[0], KNEE_JOINTS[0], HIP_JOINTS[1], KNEE_JOINTS[1])
#: Position servos, one per actuated joint, same order.
ACTUATORS = tuple(f"servo_{j}" for j in ACTUATED_JOINTS)

FEMURS = ("femur_l", "femur_r")  #: bodies and their geoms
TIBIAE = ("tibia_l", "tibia_r")  #: bodies and their geoms
TARSI = ("tarsus_l", "tarsus_r")  #: sphere geoms at the tibia tips
TARSUS_SITES = ("tarsus_site_l", "tarsus_site_r")
TOUCH_SENSORS = ("touch_l", "touch_r")  #: on the tarsus sites (input I5)
#: Contact sensors the engine records from (``penetration``, ``wall_contact``):
#: the signed distance of the creature's deepest contact, and per wall geom of
#: the scene the number of its contacts: wall_contact0, wall_contact1, ...
DEEPEST_CONTACT = "deepest_contact"
WALL_CONTACT = "wall_contact"

CAMERA_TRACK = "track"  #: follows the body from the side
CAMERA_SIDE = "side"  #: fixed, looking at the start
