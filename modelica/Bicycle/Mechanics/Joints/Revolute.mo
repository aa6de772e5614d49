within Bicycle.Mechanics.Joints;
model Revolute "Free revolute joint (no torque)"
  extends Bicycle.Mechanics.Joints.PartialRevolute;
equation
  tau = 0;
  Ej = 0;
  Fa = tau - frame_b.F[k];
  annotation(Documentation(info = "<html><p>A revolute joint without friction or drive: see
<a href=\"modelica://Bicycle.Mechanics.Joints.PartialRevolute\">PartialRevolute</a>.</p></html>"));
end Revolute;
