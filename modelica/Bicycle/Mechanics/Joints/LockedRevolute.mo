within Bicycle.Mechanics.Joints;
model LockedRevolute "Revolute joint held at its angle: its equation of motion is replaced by J*der(omega) = 0; the torque input has no effect"
  extends Bicycle.Mechanics.Joints.PartialActuatedRevolute(final omega0 = 0);
  parameter Bicycle.Units.MomentOfInertia J = 1 "Coefficient of the lock's equation J*der(omega) = 0 (any positive value gives the same motion)";
equation
  // The generalized force of coordinate k of the bodies beyond (the joint's equation of motion)
  // drops out of the system and -J*du[k] takes its place; the lock's torque is whatever that takes
  Fa = -J*frame_a.du[k];
  tau = Fa + frame_b.F[k];
  Ej = 0;
  annotation(
    Icon(graphics = {
      Line(points = {{-40, -40}, {40, 40}}, color = {255, 0, 0}, thickness = 1),
      Line(points = {{-40, 40}, {40, -40}}, color = {255, 0, 0}, thickness = 1)}),
    Documentation(info = "<html><p>The joint of <a
href=\"modelica://Bicycle.Mechanics.Joints.PartialRevolute\">PartialRevolute</a>, locked: frame_b is
turned by the joint's angle as with a free joint, and the joint keeps its coordinate (column
<code>k</code>), but Kane's equation of that coordinate reads <code>J*der(omega) = 0</code>. The
lock's torque is whatever that takes; being an internal torque pair of the joint, it enters no other
equation of motion. The joint starts at rest (<code>omega0 = 0</code>) and keeps its initial angle
<code>angle0</code>: the bodies beyond move as if rigidly fixed at that angle. The torque input
<code>tau_in</code> has no effect.</p></html>"));
end LockedRevolute;
