"""Names of every MJCF element that Python reads (one place, no scattered strings)."""

BODY = "body"  #: the thorax/abdomen; its frame origin is the body centre
ROOT_JOINT = "root"  #: the free joint of the body
FLOOR = "floor"

SIDES = ("l", "r")  #: left (+y) and right (-y)

# Hind legs: body–femur ("hip") and femur–tibia ("knee") hinges, both actuated.
HIP_JOINTS = ("hip_l", "hip_r")
KNEE_JOINTS = ("knee_l", "knee_r")
#: The four actuated joints in the paper's input order I1–I4.
ACTUATED_JOINTS = ("hip_l", "knee_l", "hip_r", "knee_r")
#: Position servos, one per actuated joint, same order.
ACTUATORS = tuple(f"servo_{j}" for j in ACTUATED_JOINTS)

FEMUR_BODIES = ("femur_l", "femur_r")
TIBIA_BODIES = ("tibia_l", "tibia_r")
TARSUS_GEOMS = ("tarsus_l", "tarsus_r")
TARSUS_SITES = ("tarsus_site_l", "tarsus_site_r")
TOUCH_SENSORS = ("touch_l", "touch_r")

CAMERA_TRACK = "track"
CAMERA_SIDE = "side"
