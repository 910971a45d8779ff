// Wheels as tyres: which collision shapes are wheels, and where a tyre touches a plane.
//
// A wheel is a cylinder spinning about its own axis on a revolute or continuous joint. Both
// engines give it the same contact model, a tyre: the cylinder with its tread rounded by half
// its width (the set of points within width/2 of a flat disk of radius `radius - width/2` in the
// wheel's mid-plane). On flat ground that touches in the mid-plane at the full radius, at one
// point. A flat tread would touch at its two rims instead: a wheel on a curve then scrubs (its
// rims roll on circles of different radii at one spin rate), which yaws a car out of its turn,
// and each rim costs the solver its own contact rows.
#pragma once

#include "conde_physics/math.h"
#include "conde_physics/model.h"

namespace conde_physics {

// True when collision `collision` of body `body` is a wheel: a cylinder whose axis is the axis
// of a revolute or continuous joint that carries `body` (the joint's child).
bool isWheelCollision(const ArticulatedModel& model, int body, const CollisionSpec& collision);

// True when a cylinder of this size can be rounded into a tyre (its half width is below its
// radius).
bool canBeTyre(double radius_m, double length_m);

struct TyreContact {
  Vec3 point_m;    // deepest point of the tyre, world coordinates
  double depth_m;  // how far it lies below the plane (> 0: touching)
};

enum class TyreOnPlane {
  kApart,     // the tyre does not reach the plane
  kTouching,  // one contact, filled in
  kOnFace,    // the wheel lies on its side (axis within ~15 degrees of the normal): it rests on
              // its flat face, not on one point; collide it as a plain cylinder
};

// Contact of a tyre (centre and unit spin axis in world coordinates, radius and full width)
// with the plane {x : normal . x = offset_m} (unit normal, the solid side below it).
TyreOnPlane tyreOnPlane(const Vec3& centre_m, const Vec3& axis, double radius_m, double width_m, const Vec3& normal,
                        double offset_m, TyreContact& contact);

}  // namespace conde_physics
