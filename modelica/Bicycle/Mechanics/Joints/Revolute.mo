within Bicycle.Mechanics.Joints;
model Revolute "Free revolute joint (no torque)"
  extends Bicycle.Mechanics.Joints.PartialRevolute;
equation
  tau = 0;
  annotation(Documentation(info = "<html><p>A revolute joint without friction or drive: see
<code>PartialRevolute</code>.</p></html>"));
end Revolute;
