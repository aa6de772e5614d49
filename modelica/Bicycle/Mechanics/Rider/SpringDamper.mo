within Bicycle.Mechanics.Rider;
model SpringDamper "Linear rotational spring and damper acting on one generalized coordinate (a hinge angle)"
  constant Integer n = 7 "Number of generalized speeds";
  constant Real sel[n] "Selects the hinge angle among the generalized coordinates (the unit vector of its index)";
  parameter Real k(final quantity = "RotationalSpringConstant", final unit = "N.m/rad", min = 0) "Stiffness (torque per angle)";
  parameter Real d(final quantity = "RotationalDampingConstant", final unit = "N.m.s/rad", min = 0) "Damping (torque per rate)";
  Bicycle.Mechanics.Interfaces.Frame frame_a(n = n) "A frame of the system: the element reads the coordinate and its speed from it";
  Bicycle.Units.Angle phi "Hinge angle (spring neutral at 0)";
  Bicycle.Units.AngularVelocity omega "Hinge rate";
  Bicycle.Units.Torque tau "Spring and damper torque on the hinge's turning side: -k*phi - d*omega";
protected
  Real selq[n] "sel .* q (rad)";
  Real selu[n] "sel .* u (rad/s)";
equation
  for j in 1:n loop
    selq[j] = sel[j]*frame_a.q[j];
    selu[j] = sel[j]*frame_a.u[j];
  end for;
  phi = sum(selq);
  omega = sum(selu);
  tau = -k*phi - d*omega;
  // No mass; the torque pair of the hinge is the generalized force tau of the hinge coordinate only
  frame_a.M = zeros(n, n);
  frame_a.f = tau*sel;
  frame_a.Ep = 0.5*k*phi^2;
  annotation(Documentation(info = "<html><p>A spring with stiffness <code>k</code> (neutral at zero angle)
and a viscous damper <code>d</code> between the two sides of a hinge whose angle is the generalized
coordinate <code>q[k]</code> selected by <code>sel</code>. The torque pair <code>tau</code> (on the turning
side), <code>-tau</code> (on the other) has the generalized force <code>tau</code> in coordinate
<code>k</code> and none in the others, so the element can be attached to any frame of the system; it
adds the spring's potential energy <code>k phi^2/2</code> to the energy flow <code>Ep</code>.</p></html>"));
end SpringDamper;
