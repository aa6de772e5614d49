within Bicycle.Mechanics;
model Ground "Flat ground carrying a bicycle: the rear frame's attitude and position, the rolling constraints of both wheels and Kane's equations"
  constant Integer n = 6 "Number of generalized speeds of the system: columns 1 to 3 the dependent speeds (yaw, pitch, spin of the front wheel), 4 the roll rate, 5 to n the speeds the joints own";
  parameter Bicycle.Units.Acceleration g(min = 0) = 9.81 "Gravitational acceleration (along the ground z axis, which points down)";
  parameter Bicycle.Units.Position x0 = 0 "Initial x coordinate of the rear contact point";
  parameter Bicycle.Units.Position y0 = 0 "Initial y coordinate of the rear contact point (right)";
  parameter Bicycle.Units.Angle psi0 = 0 "Initial yaw angle";
  parameter Bicycle.Units.Angle phi0 = 0 "Initial roll angle";
  parameter Bicycle.Units.AngularVelocity u_phi0 = 0 "Initial roll rate";
  parameter Bicycle.Units.Angle theta_guess = 0 "Starting value of the Newton iteration for the initial pitch";
  Bicycle.Interfaces.RealInput T_phi(final quantity = "Torque", final unit = "N.m") "Roll torque T_phi on the rear frame about the (horizontal) roll axis, positive tending to lean right (disturbance)"
    annotation(Placement(transformation(extent = {{-170, -5}, {-160, 5}})));
  Bicycle.Mechanics.Interfaces.Frame_b frame_b(n = n) "Rear frame at the centre of the wheel that carries it (the rear axle): attitude from yaw, roll and pitch, motion from the rolling of that wheel"
    annotation(Placement(transformation(origin = {-150, 20}, extent = {{-5, -5}, {5, 5}}, rotation = 90)));
  Bicycle.Mechanics.Interfaces.GroundContact rearContact(n = n) "Contact of the wheel whose hub is frame_b: its contact point does not move, which fixes the motion of frame_b"
    annotation(Placement(transformation(extent = {{-105, 15}, {-95, 25}})));
  Bicycle.Mechanics.Interfaces.GroundContact frontContact(n = n) "Contact of the front wheel: its rolling constraints fix the dependent speeds"
    annotation(Placement(transformation(extent = {{95, 15}, {105, 25}})));
  Bicycle.Units.Position x(start = x0, fixed = true) "x coordinate (forward at yaw 0) of the rear contact point";
  Bicycle.Units.Position y(start = y0, fixed = true) "y coordinate (right at yaw 0) of the rear contact point";
  Bicycle.Units.Angle psi(start = psi0, fixed = true) "Yaw angle psi of the rear frame, positive turning right";
  Bicycle.Units.Angle phi(start = phi0, fixed = true) "Roll angle phi of the rear frame, positive leaning right";
  Bicycle.Units.Angle theta(start = theta_guess, fixed = false) "Pitch angle theta of the rear frame, positive nose up (solved from the initial equation)";
  Bicycle.Units.AngularVelocity u_phi(start = u_phi0, fixed = true) "Roll rate (independent speed)";
  output Bicycle.Units.AngularVelocity u_psi "Yaw rate (dependent speed)";
  output Bicycle.Units.AngularVelocity u_theta "Pitch rate (dependent speed)";
  output Bicycle.Units.AngularVelocity u_F "Spin rate of the front wheel relative to its hub (dependent speed)";
  output Bicycle.Units.AngularAcceleration u_psi_dot "Time derivative of u_psi";
  output Bicycle.Units.AngularAcceleration u_theta_dot "Time derivative of u_theta";
  output Bicycle.Units.AngularAcceleration u_F_dot "Time derivative of u_F";
  output Bicycle.Units.Velocity v "Forward speed of the rear contact point (velocity along the heading)";
  output Bicycle.Units.Energy E "Total mechanical energy of the bodies and springs: kinetic, gravitational (zero at the ground) and elastic";
  output Bicycle.Units.Length residual "Holonomic constraint residual: height of the front contact point above the ground (should be 0)";
protected
  constant Integer ni = n - 3 "Number of independent speeds: the roll rate and the speeds of the joints";
  Real Ax[3] "Yaw frame x axis (heading)";
  Real Ay[3] "Yaw frame y axis";
  Real Ly[3] "Roll frame y axis (rear axle)";
  Real Lz[3] "Roll frame z axis (down in the rear wheel plane)";
  Real ui[ni] "Independent speeds: the roll rate, then the joints' speeds (rad/s)";
  Real dui[ni] "Time derivatives of the independent speeds (rad/s2)";
  Real ud[3] "Dependent speeds u_psi, u_theta, u_F (rad/s)";
  Real Bi[3, ni] "Front contact rows: columns of the independent speeds (m)";
  Real Bd[3, 3] "Front contact rows: columns of the dependent speeds (m)";
  Real Ad[3, ni] "Dependent speeds ud = Ad*ui: Bd*Ad = -Bi";
  Real ad0[3] "Acceleration remainder of the dependent speeds (rad/s2): der(ud) = Ad*der(ui) + ad0";
  Real Q[ni] "Applied generalized forces of the independent speeds that act at the ground: the roll torque (N.m)";
initial equation
  residual = 0;
equation
  der(x) = rearContact.v[1];
  der(y) = rearContact.v[2];
  der(psi) = u_psi;
  der(phi) = u_phi;
  der(theta) = u_theta;
  der(u_phi) = dui[1];
  // Speeds: the roll rate is the ground's, the joints' speeds arrive through the flow us
  ui[1] = u_phi;
  for i in 2:ni loop
    ui[i] = -frame_b.us[i + 3];
  end for;
  // The front wheel's rolling rows Bi*ui + Bd*ud = 0 fix the dependent speeds (columns 1 to 3)
  for j in 1:3 loop
    Bd[1, j] = frontContact.B[1, j];
    Bd[2, j] = frontContact.B[2, j];
    Bd[3, j] = frontContact.B[3, j];
  end for;
  for i in 1:ni loop
    Bi[1, i] = frontContact.B[1, i + 3];
    Bi[2, i] = frontContact.B[2, i + 3];
    Bi[3, i] = frontContact.B[3, i + 3];
  end for;
  Bd*Ad = -Bi;
  Bd*ad0 = -frontContact.b0;
  ud = Ad*ui;
  u_psi = ud[1];
  u_theta = ud[2];
  u_F = ud[3];
  frame_b.u[1] = ud[1];
  frame_b.u[2] = ud[2];
  frame_b.u[3] = ud[3];
  for i in 1:ni loop
    frame_b.u[i + 3] = ui[i];
  end for;
  // Kane's equations for the independent speeds, T'*(sum of the generalized forces + Q) = 0 with
  // u = T*ui, T = [Ad; identity]; the connection set gives frame_b.F = -(sum over the bodies and joints)
  frame_b.du[1] = Ad[1, :]*dui + ad0[1];
  frame_b.du[2] = Ad[2, :]*dui + ad0[2];
  frame_b.du[3] = Ad[3, :]*dui + ad0[3];
  for i in 1:ni loop
    frame_b.du[i + 3] = dui[i];
  end for;
  Q[1] = T_phi;
  for i in 2:ni loop
    Q[i] = 0;
  end for;
  for i in 1:ni loop
    frame_b.F[i + 3] + Ad[1, i]*frame_b.F[1] + Ad[2, i]*frame_b.F[2] + Ad[3, i]*frame_b.F[3] = Q[i];
  end for;
  u_psi_dot = Ad[1, :]*dui + ad0[1];
  u_theta_dot = Ad[2, :]*dui + ad0[2];
  u_F_dot = Ad[3, :]*dui + ad0[3];
  // Rear frame orientation: yaw psi about the ground z, roll phi about the yaw frame x, pitch theta about the roll frame y
  Ax[1] = cos(psi);
  Ax[2] = sin(psi);
  Ax[3] = 0;
  Ay[1] = -sin(psi);
  Ay[2] = cos(psi);
  Ay[3] = 0;
  Ly = cos(phi)*Ay + sin(phi)*{0, 0, 1};
  Lz = -sin(phi)*Ay + cos(phi)*{0, 0, 1};
  for i in 1:3 loop
    frame_b.R[i, 1] = cos(theta)*Ax[i] - sin(theta)*Lz[i];
    frame_b.R[i, 2] = Ly[i];
    frame_b.R[i, 3] = sin(theta)*Ax[i] + cos(theta)*Lz[i];
    frame_b.Wp[i, 2] = Ly[i];
    frame_b.Wp[i, 3] = 0;
    frame_b.Wp[i, 4] = Ax[i];
  end for;
  frame_b.Wp[1, 1] = 0;
  frame_b.Wp[2, 1] = 0;
  frame_b.Wp[3, 1] = 1;
  for j in 5:n loop
    frame_b.Wp[1, j] = 0;
    frame_b.Wp[2, j] = 0;
    frame_b.Wp[3, j] = 0;
  end for;
  frame_b.w = u_psi*{0, 0, 1} + u_theta*Ly + u_phi*Ax;
  // der(Ax) = u_psi Ay, der(Ly) = (u_psi e_z + u_phi Ax) x Ly = -u_psi cos(phi) Ax + u_phi Lz
  frame_b.al0 = u_phi*u_psi*Ay + u_theta*(-u_psi*cos(phi)*Ax + u_phi*Lz);
  // The rear wheel rolls: its material contact point does not move, which gives the motion of its centre
  frame_b.Vp = -rearContact.Bc;
  frame_b.a0 = -rearContact.bc0;
  frame_b.r[1] = x - rearContact.rho[1];
  frame_b.r[2] = y - rearContact.rho[2];
  frame_b.r[3] = -rearContact.rho[3];
  frame_b.g = g;
  E = -frame_b.E;
  v = rearContact.v[1]*cos(psi) + rearContact.v[2]*sin(psi);
  residual = frontContact.p[3];
  annotation(
    Icon(coordinateSystem(preserveAspectRatio = true, extent = {{-160, -20}, {160, 20}}), graphics = {
      Rectangle(extent = {{-160, 20}, {160, 4}}, lineColor = {128, 128, 128}, fillColor = {128, 128, 128}, fillPattern = FillPattern.Backward, pattern = LinePattern.None),
      Line(points = {{-160, 20}, {160, 20}}, color = {0, 0, 0}, thickness = 1),
      Text(extent = {{-60, -5}, {60, -17}}, textString = "%name", textColor = {0, 0, 255})}),
    Documentation(info = "<html>
<p>The ground of the generalized-coordinate components (Kane's method): a component like any other,
connected to the bicycle by its frame <code>frame_b</code> (the rear axle, where the rear frame and
the rear wheel hang) and by the two wheel contacts. It owns the coordinates of the rear frame
relative to the ground: the position <code>x, y</code> of the rear contact point, yaw
<code>psi</code>, roll <code>phi</code> and pitch <code>theta</code>, <code>R = Rz(psi) Rx(phi)
Ry(theta)</code>; every other coordinate belongs to a joint or a wheel.</p>
<p>The generalized speeds are numbered: columns 1 to 3 the dependent speeds (yaw rate
<code>u_psi</code>, pitch rate <code>u_theta</code>, spin rate <code>u_F</code> of the wheel at
<code>frontContact</code>, whose wheel must have <code>k = 3</code> and <code>rolling = true</code>),
column 4 the roll rate <code>u_phi</code>, columns 5 to <code>n</code> the speeds that joints and
wheels own (each joint is told its column <code>k</code>; the assembly says <code>n</code> once). The
joints' speeds reach the ground through the flow <code>us</code>; the front wheel's rolling rows
<code>Bi*ui + Bd*ud = 0</code> give the dependent speeds <code>ud = Ad*ui</code>
(<code>Bd*Ad = -Bi</code>) and their acceleration remainder (<code>Bd*ad0 = -b0</code>). With
<code>u = T*ui</code>, <code>T = [Ad; identity]</code>, Kane's equations of the constrained system are
<code>T'*(sum of F + Q) = 0</code>, where the connection set of <code>frame_b</code> delivers the sum
of the generalized active and inertia forces of all bodies and joints (written with the
generalized accelerations <code>du = T*der(ui) + D*ad0</code>), and <code>Q</code> holds the roll
torque <code>T_phi</code>. The compiler solves this linear system in <code>der(ui)</code>.</p>
<p>The rear wheel (the one whose hub is <code>frame_b</code> and whose contact is
<code>rearContact</code>) carries the rear frame: its material contact point does not move, so
<code>frame_b</code> moves with the partial velocities <code>-Bc</code> of that point relative to the
wheel centre. The pitch is integrated with the velocity form of the holonomic constraint; its
initial value solves the initial equation <code>residual = 0</code> (the front contact point on the
ground), starting from <code>theta_guess</code>. The energy <code>E</code> is the sum the bodies and
springs report through the connector.</p>
</html>"));
end Ground;
