within Bicycle.Wheels;
partial model PartialWheel "Rigid axisymmetric wheel spinning about the y axis of its hub frame, rolling on the ground z = 0; it owns its spin coordinate"
  extends Bicycle.Icons.Wheel;
  constant Integer n = 6 "Number of generalized speeds of the system";
  constant Integer k = 1 "Column of the wheel's spin rate among the generalized speeds";
  constant Boolean rolling = false "= true: the spin rate is one of the dependent speeds, fixed by the rolling constraints and given by the ground (the front wheel); false: the wheel owns it as a state";
  parameter Bicycle.Units.Length r(min = 1e-6) "Wheel radius: height of the centre of the upright wheel";
  parameter Bicycle.Units.Mass m "Mass";
  parameter Bicycle.Units.MomentOfInertia Ixx "Diametral moment of inertia (Ixx = Izz)";
  parameter Bicycle.Units.MomentOfInertia Iyy "Moment of inertia about the spin axis";
  parameter Bicycle.Units.Angle angle0 = 0 "Initial spin angle relative to the hub";
  parameter Bicycle.Units.AngularVelocity spin0 = 0 "Initial spin rate relative to the hub (a wheel that owns it)";
  Bicycle.Mechanics.Interfaces.Frame_a hub(n = n) "Hub frame: origin at the wheel centre, y axis = spin axis"
    annotation(Placement(transformation(origin = {0, 100}, extent = {{-16, -16}, {16, 16}}, rotation = 90)));
  Bicycle.Mechanics.Interfaces.WheelContact contact(n = n) "Rolling contact with the ground"
    annotation(Placement(transformation(extent = {{-16, -116}, {16, -84}})));
  Bicycle.Units.Angle angle(start = angle0, fixed = true) "Spin angle relative to the hub";
  // no fixed: a state that starts at spin0 when the wheel owns it, else the ground's dependent speed
  Bicycle.Units.AngularVelocity spin(start = spin0) "Spin rate relative to the hub: the generalized speed k";
  Real e[3] "Unit vector in the wheel plane pointing most steeply down (ground axes)";
  Real e_dot[3] "Time derivative of e (1/s)";
  Real rho[3] "Vector from the wheel centre to the contact point (ground axes) (m)";
  Real rho_dot[3] "Time derivative of rho (m/s)";
  Real ax[3] "Spin axis in ground axes";
  Real ax_dot[3] "Time derivative of the spin axis (1/s)";
  Real s "Vertical component of the spin axis";
  Real cs "sqrt(1 - s^2)";
  Real s_dot "Time derivative of s (1/s)";
  Real ww[3] "Angular velocity of the wheel (rad/s)";
  Real Wpw[3, n] "Partial angular velocities of the wheel";
  Real alw[3] "Angular acceleration remainder of the wheel (rad/s2)";
  Real IN[3, 3] "(Iyy - Ixx) ax ax': the inertia tensor in ground axes is IN + Ixx*identity(3) (kg.m2)";
  Real H[3] "Angular momentum about the centre (kg.m2/s)";
  Real aw[3] "Angular acceleration of the wheel: Wpw*du + alw (rad/s2)";
  Real ac[3] "Acceleration of the centre: Vp*du + a0 (m/s2)";
  Real vc[3] "Velocity of the centre: Vp*u (m/s)";
  Real Ia[3] "IN*aw (N.m)";
  Real F[3] "Gravity minus m*ac (N)";
  Real T[3] "-I aw - ww x H (N.m)";
equation
  der(angle) = spin;
  if rolling then
    spin = hub.u[k];
  else
    der(spin) = hub.du[k];
  end if;
  // Geometry of the wheel plane: e = (e_z - s ax)/sqrt(1 - s^2), s = e_z.ax
  ax[1] = hub.R[1, 2];
  ax[2] = hub.R[2, 2];
  ax[3] = hub.R[3, 2];
  ax_dot[1] = hub.w[2]*ax[3] - hub.w[3]*ax[2];
  ax_dot[2] = hub.w[3]*ax[1] - hub.w[1]*ax[3];
  ax_dot[3] = hub.w[1]*ax[2] - hub.w[2]*ax[1];
  s = ax[3];
  cs = sqrt(1 - s^2);
  s_dot = ax_dot[3];
  e[1] = -s*ax[1]/cs;
  e[2] = -s*ax[2]/cs;
  e[3] = cs;
  for i in 1:3 loop
    e_dot[i] = (-s_dot*ax[i] - s*ax_dot[i])/cs + e[i]*s*s_dot/cs^2;
  end for;
  // Kinematics of the wheel body
  ww = hub.w + ax*spin;
  for j in 1:n loop
    Wpw[1, j] = hub.Wp[1, j] + (if j == k then ax[1] else 0);
    Wpw[2, j] = hub.Wp[2, j] + (if j == k then ax[2] else 0);
    Wpw[3, j] = hub.Wp[3, j] + (if j == k then ax[3] else 0);
  end for;
  alw = hub.al0 + ax_dot*spin;
  // Axisymmetric inertia Ixx (I - ax ax') + Iyy ax ax': independent of the spin angle
  for i in 1:3 loop
    IN[i, 1] = (Iyy - Ixx)*ax[i]*ax[1];
    IN[i, 2] = (Iyy - Ixx)*ax[i]*ax[2];
    IN[i, 3] = (Iyy - Ixx)*ax[i]*ax[3];
  end for;
  H = IN*ww + Ixx*ww;
  aw = Wpw*hub.du + alw;
  ac = hub.Vp*hub.du + hub.a0;
  vc = hub.Vp*hub.u;
  Ia = IN*aw + Ixx*aw;
  F[1] = -m*ac[1];
  F[2] = -m*ac[2];
  F[3] = m*(hub.g - ac[3]);
  T[1] = -Ia[1] - (ww[2]*H[3] - ww[3]*H[2]);
  T[2] = -Ia[2] - (ww[3]*H[1] - ww[1]*H[3]);
  T[3] = -Ia[3] - (ww[1]*H[2] - ww[2]*H[1]);
  // Kane's generalized active and inertia forces of the wheel; its own speed unless the ground gives it
  hub.F = transpose(hub.Vp)*F + transpose(Wpw)*T;
  for j in 1:n loop
    hub.us[j] = if j == k and not rolling then spin else 0;
  end for;
  hub.E = 0.5*m*(vc[1]^2 + vc[2]^2 + vc[3]^2) + 0.5*(ww[1]*H[1] + ww[2]*H[2] + ww[3]*H[3]) - m*hub.g*hub.r[3];
  // Contact: material point of the wheel at rho, geometric point moving with rho_dot
  contact.rho = rho;
  contact.p = hub.r + rho;
  for j in 1:n loop
    contact.Bc[1, j] = Wpw[2, j]*rho[3] - Wpw[3, j]*rho[2];
    contact.Bc[2, j] = Wpw[3, j]*rho[1] - Wpw[1, j]*rho[3];
    contact.Bc[3, j] = Wpw[1, j]*rho[2] - Wpw[2, j]*rho[1];
  end for;
  contact.bc0[1] = alw[2]*rho[3] - alw[3]*rho[2] + ww[2]*rho_dot[3] - ww[3]*rho_dot[2];
  contact.bc0[2] = alw[3]*rho[1] - alw[1]*rho[3] + ww[3]*rho_dot[1] - ww[1]*rho_dot[3];
  contact.bc0[3] = alw[1]*rho[2] - alw[2]*rho[1] + ww[1]*rho_dot[2] - ww[2]*rho_dot[1];
  contact.B = hub.Vp + contact.Bc;
  contact.b0 = hub.a0 + contact.bc0;
  contact.v = vc + rho_dot;
  annotation(
    Icon(graphics = {
      Line(points = {{0, 16}, {0, 100}}, color = {95, 95, 95}, thickness = 0.5)}),
    Documentation(info = "<html>
<p>The wheel's mass centre is the hub origin, its spin axis the hub's y axis. The wheel owns its
spin coordinate: the angle is a state, and the rate is either a state too (the generalized speed
in column <code>k</code>, which the wheel adds to the flow <code>us</code>; its acceleration is
<code>du[k]</code>) or, for the wheel with <code>rolling = true</code>, one of the dependent speeds
that the ground solves from the rolling constraints and gives in <code>u[k]</code>. Because the
wheel is axisymmetric its inertia tensor in ground axes, <code>Ixx (I - a a') + Iyy a a'</code> with
the axle <code>a</code>, does not depend on the spin angle.</p>
<p>Contact: the material point of the wheel at <code>rho</code> from the centre has the velocity
<code>B*u</code> with <code>B = Vp + Bc</code>, <code>Bc = Wp_wheel x rho</code>, and the acceleration
<code>B*du + b0</code>, <code>b0 = a0 + bc0</code>, <code>bc0 = al0_wheel x rho + w_wheel x der(rho)</code>.
The contact vector <code>rho</code> and its rate are left to the extending classes; they use
<code>e = (e_z - s a)/sqrt(1 - s^2)</code>, <code>s = e_z.a</code>, the unit vector in the wheel
plane pointing most steeply down, and its rate <code>e_dot</code> (written out analytically).</p>
</html>"));
end PartialWheel;
