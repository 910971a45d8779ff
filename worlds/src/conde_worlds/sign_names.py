"""The twelve vertical traffic signs of the V1 challenge by name and family, without drawing them
(no OpenCV: the referee and the competition runner only need the names; traffic_signs.py draws).

    danger (white triangle, red border):  other_danger, uneven_road, cattle, road_narrows
    information (blue square):            parking, recommended_60, hospital, pedestrian_crossing
    mandatory (blue disc):                turn_left, lights_on, roundabout, buses
"""

DANGER = ("other_danger", "uneven_road", "cattle", "road_narrows")
INFORMATION = ("parking", "recommended_60", "hospital", "pedestrian_crossing")
MANDATORY = ("turn_left", "lights_on", "roundabout", "buses")
SIGNS = DANGER + INFORMATION + MANDATORY
FAMILY = {**{s: "danger" for s in DANGER}, **{s: "information" for s in INFORMATION},
          **{s: "mandatory" for s in MANDATORY}}
