within Bicycle.Mechanics.Rider;
partial model PartialHinge "Interface of the rider's hip hinge between the rear frame (frame_a) and the upper body (frame_b)"
  final constant Integer n = 7 "Number of generalized speeds (those of Rider.Ground)";
  final constant Real sel[n] = {0, 0, 0, 0, 0, 0, 1} "Selects the lean angle among the generalized coordinates: coordinate 7 of Rider.Ground";
  Bicycle.Mechanics.Interfaces.Frame frame_a(n = n) "Hinge point, fixed to the rear frame (axes of the rear frame)";
  Bicycle.Mechanics.Interfaces.Frame frame_b(n = n) "Hinge point, fixed to the upper body (axes of the upper body)";
  Bicycle.Interfaces.RealInput tau_in(final quantity = "Torque", final unit = "N.m") "Lean torque of the rider on the upper body about the hinge axis (reaction on the rear frame), positive tending to lean the upper body right";
  annotation(Documentation(info = "<html><p>The constraining class of the replaceable hip hinge of
<a href=\"modelica://Bicycle.Bicycles.WhippleRider\">WhippleRider</a>: two frames at the hinge point,
one on the rear frame, one on the upper body, and the rider's lean torque as input. The hinge axis
is the x axis of <code>frame_a</code> (longitudinal); the lean angle is the generalized coordinate
selected by <code>sel</code>.</p></html>"));
end PartialHinge;
