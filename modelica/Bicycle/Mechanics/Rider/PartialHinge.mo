within Bicycle.Mechanics.Rider;
partial model PartialHinge "Hip hinge between the rear frame and the rider's upper body: frames, lean torque and the lean coordinate"
  extends Bicycle.Icons.Hinge;
  constant Integer n = 7 "Number of generalized speeds of the system";
  constant Integer k = 7 "Column of the lean rate among the generalized speeds";
  parameter Bicycle.Units.Angle angle0 = 0 "Initial lean angle of the upper body relative to the rear frame";
  parameter Bicycle.Units.AngularVelocity omega0 = 0 "Initial lean rate";
  Bicycle.Mechanics.Interfaces.Frame_a frame_a(n = n) "Hinge point, fixed to the rear frame (axes of the rear frame)"
    annotation(Placement(transformation(origin = {0, -100}, extent = {{-16, -16}, {16, 16}}, rotation = 90)));
  Bicycle.Mechanics.Interfaces.Frame_b frame_b(n = n) "Hinge point, fixed to the upper body (axes of the upper body)"
    annotation(Placement(transformation(origin = {0, 100}, extent = {{-16, -16}, {16, 16}}, rotation = 90)));
  Bicycle.Interfaces.RealInput tau_in(final quantity = "Torque", final unit = "N.m") "Lean torque of the rider on the upper body about the hinge axis (reaction on the rear frame), positive tending to lean the upper body right"
    annotation(Placement(transformation(extent = {{-140, -60}, {-100, -20}})));
  Bicycle.Units.Angle angle "Lean angle of the upper body relative to the rear frame, positive leaning right";
  Bicycle.Units.AngularVelocity omega "Lean rate der(angle)";
  annotation(Documentation(info = "<html><p>The constraining class of the replaceable hip hinge of
<a href=\"modelica://Bicycle.Bicycles.WhippleRider\">WhippleRider</a>: two frames at the hinge point,
one on the rear frame, one on the upper body, the rider's lean torque as input, and the lean
coordinate (angle and rate), which the hinge owns in column <code>k</code> of the generalized
speeds. The hinge axis is the x axis of <code>frame_a</code> (longitudinal).</p></html>"));
end PartialHinge;
