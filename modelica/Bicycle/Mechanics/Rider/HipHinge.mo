within Bicycle.Mechanics.Rider;
model HipHinge "Hip hinge: revolute about the rear frame's x axis, driven by the rider's lean torque, with passive stiffness and damping"
  extends Bicycle.Mechanics.Rider.PartialHinge;
  parameter Real k(final quantity = "RotationalSpringConstant", final unit = "N.m/rad", min = 0) = 0 "Passive stiffness of the hip (lean torque per lean angle)";
  parameter Real d(final quantity = "RotationalDampingConstant", final unit = "N.m.s/rad", min = 0) = 0 "Passive damping of the hip (lean torque per lean rate)";
  // sel written out (= PartialHinge.sel): pymoca does not substitute an array constant given as a modifier value
  Bicycle.Mechanics.Joints.ActuatedRevolute revolute(n = n, frame_a(n = n), frame_b(n = n), sel = {0, 0, 0, 0, 0, 0, 1}, final nx = 1, final ny = 0, final nz = 0) "Revolute about the longitudinal axis, driven by the lean torque";
  Bicycle.Mechanics.Rider.SpringDamper passive(n = n, frame_a(n = n), sel = {0, 0, 0, 0, 0, 0, 1}, k = k, d = d) "Passive stiffness and damping of the hip";
equation
  connect(frame_a, revolute.frame_a);
  connect(revolute.frame_b, frame_b);
  connect(frame_a, passive.frame_a);
  connect(tau_in, revolute.tau_in);
  annotation(Documentation(info = "<html><p>The upper body (<code>frame_b</code>) turns relative to the
rear frame (<code>frame_a</code>) about the x axis of <code>frame_a</code> by the lean angle, the
generalized coordinate selected by <code>sel</code>. The hinge torque on the upper body is
<code>tau_in - k*beta - d*der(beta)</code>: the rider's lean torque plus a passive spring (neutral
upright) and damper; the reaction acts on the rear frame.</p></html>"));
end HipHinge;
