within Bicycle.Mechanics.Joints;
partial model PartialActuatedRevolute "Revolute joint with a torque input: the constraining class of the hinges that may be locked"
  extends Bicycle.Mechanics.Joints.PartialRevolute;
  Bicycle.Interfaces.RealInput tau_in(final quantity = "Torque", final unit = "N.m") "Torque on frame_b about the axis (reaction on frame_a)"
    annotation(Placement(transformation(origin = {0, 120}, extent = {{-20, -20}, {20, 20}}, rotation = -90)));
  annotation(Documentation(info = "<html><p>A <a href=\"modelica://Bicycle.Mechanics.Joints.PartialRevolute\">PartialRevolute</a>
with a torque input: what <a href=\"modelica://Bicycle.Mechanics.Joints.ActuatedRevolute\">ActuatedRevolute</a>
(driven by the input) and <a href=\"modelica://Bicycle.Mechanics.Joints.LockedRevolute\">LockedRevolute</a>
(held; the input has no effect) have in common, so that a replaceable hinge can be either.</p></html>"));
end PartialActuatedRevolute;
