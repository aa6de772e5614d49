within Bicycle.Mechanics;
partial model PartialGround "Root of a bicycle on flat ground with n generalized speeds: coordinates and speeds, dependent-speed elimination, Kane's equations"
  // n and ni have no default: with one, pymoca 0.12 used it (not the value the extending class gives)
  // for the dimensions of the connectors below and in the extending class's component modifiers (n = n)
  constant Integer n "Number of generalized speeds: u_phi, u_delta, u_R (independent), u_psi, u_theta, u_F (dependent), then n - 6 further independent speeds of the extending class";
  constant Integer ni "Number of independent speeds, n - 3 (given with n: pymoca 0.12 would not recompute a binding ni = n - 3)";
  parameter Bicycle.Units.Position x0 = 0 "Initial x coordinate of the rear contact point";
  parameter Bicycle.Units.Position y0 = 0 "Initial y coordinate of the rear contact point (right)";
  parameter Bicycle.Units.Angle psi0 = 0 "Initial yaw angle";
  parameter Bicycle.Units.Angle phi0 = 0 "Initial roll angle";
  parameter Bicycle.Units.Angle delta0 = 0 "Initial steer angle";
  parameter Bicycle.Units.Angle thetaR0 = 0 "Initial rear wheel angle";
  parameter Bicycle.Units.Angle thetaF0 = 0 "Initial front wheel angle";
  parameter Bicycle.Units.AngularVelocity u_phi0 = 0 "Initial roll rate";
  parameter Bicycle.Units.AngularVelocity u_delta0 = 0 "Initial steer rate";
  parameter Bicycle.Units.AngularVelocity u_R0 = -16.666666666666668 "Initial rear wheel rate (relative to the rear frame); forward speed v = -u_R0*rR when upright (default: 5 m/s for rR = 0.3 m)";
  parameter Bicycle.Units.Angle theta_guess = 0 "Starting value of the Newton iteration for the initial pitch";
  output Bicycle.Units.AngularVelocity u_psi "Yaw rate (dependent speed)";
  output Bicycle.Units.AngularVelocity u_theta "Pitch rate (dependent speed)";
  output Bicycle.Units.AngularVelocity u_F "Front wheel rate relative to the front frame (dependent speed)";
  output Real u_psi_dot(final quantity = "AngularAcceleration", final unit = "rad/s2") "Time derivative of u_psi";
  output Real u_theta_dot(final quantity = "AngularAcceleration", final unit = "rad/s2") "Time derivative of u_theta";
  output Real u_F_dot(final quantity = "AngularAcceleration", final unit = "rad/s2") "Time derivative of u_F";
  output Bicycle.Units.Velocity v "Forward speed of the rear contact point (velocity along the heading)";
  output Real E(final quantity = "Energy", final unit = "J") "Total energy: kinetic + potential (gravity, zero at the ground, and the springs of the components)";
  output Bicycle.Units.Length residual "Holonomic constraint residual: height of the front contact point above the ground (should be 0)";
  Bicycle.Mechanics.Interfaces.Frame rear(n = n) "Rear frame at the rear axle (orientation from yaw, roll, pitch; its motion follows from the rear contact)";
  Bicycle.Mechanics.Interfaces.ContactRows rearContact(n = n) "Rear wheel contact: its rows are imposed (they determine the rear axle's motion)";
  Bicycle.Mechanics.Interfaces.ContactRows frontContact(n = n) "Front wheel contact: its rows determine the dependent speeds";
protected
  constant Real S[n, ni] "Columns of the independent speeds in u (u = S*ui + D*ud; given by the extending class)";
  constant Real D[n, 3] "Columns of the dependent speeds u_psi, u_theta, u_F (coordinates 4, 5, 6; given by the extending class)";
  Real Ax[3] "Yaw frame x axis (heading)";
  Real Ay[3] "Yaw frame y axis";
  Real Ly[3] "Roll frame y axis (rear axle)";
  Real Lz[3] "Roll frame z axis (down in the rear wheel plane)";
  Real ui[ni] "Independent speeds (rad/s)";
  Real dui[ni] "Time derivatives of the independent speeds (rad/s2)";
  Real Bi[3, ni] "Front contact rows: columns of the independent speeds (m)";
  Real Bd[3, 3] "Front contact rows: columns of the dependent speeds (m)";
  Real Ad[3, ni] "Dependent speeds u_d = Ad*ui: Bd*Ad = -Bi";
  Real ad0[3] "Acceleration remainder of the dependent speeds (rad/s2): der(u_d) = Ad*der(ui) + ad0";
  Real T[n, ni] "u = T*ui: S + D*Ad";
  Real Mt[n, n] "Generalized mass matrix of all bodies (kg.m2)";
  Real ft[n] "Generalized forces of all bodies and loads without the der(u) terms (N.m)";
  Real fe[n] "ft - Mt*D*ad0 (N.m)";
  Real Mr[ni, ni] "Reduced mass matrix T'*Mt*T (kg.m2)";
  Real fr[ni] "Reduced generalized forces T'*fe (N.m)";
  Real Mu[n] "Mt*u (kg.m2/s)";
  Real uRow[1, n] "The generalized speeds as a row matrix (rad/s)";
  Real K2[1] "Twice the kinetic energy u'*Mt*u (J)";
initial equation
  residual = 0;
equation
  // The extending class declares the coordinates and the independent speeds (the states, in the
  // order of its FMU: pymoca lists a class's own elements before the inherited ones) and binds
  // rear.q, the independent elements of rear.u, ui[4:ni], dui, rearContact.p[1:2], ft[1] (with
  // the roll torque) and the columns 7 to n of rear.Wp.
  // Generalized coordinates: q = {phi, delta, thetaR, psi, theta, thetaF, ...}, der(q) = u
  ui[1] = rear.u[1];
  ui[2] = rear.u[2];
  ui[3] = rear.u[3];
  rear.u[4] = u_psi;
  rear.u[5] = u_theta;
  rear.u[6] = u_F;
  // Rear frame orientation: yaw psi = q[4] about the ground z, roll phi = q[1] about the yaw frame x, pitch theta = q[5] about the roll frame y
  Ax[1] = cos(rear.q[4]);
  Ax[2] = sin(rear.q[4]);
  Ax[3] = 0;
  Ay[1] = -sin(rear.q[4]);
  Ay[2] = cos(rear.q[4]);
  Ay[3] = 0;
  Ly = cos(rear.q[1])*Ay + sin(rear.q[1])*{0, 0, 1};
  Lz = -sin(rear.q[1])*Ay + cos(rear.q[1])*{0, 0, 1};
  for i in 1:3 loop
    rear.R[i, 1] = cos(rear.q[5])*Ax[i] - sin(rear.q[5])*Lz[i];
    rear.R[i, 2] = Ly[i];
    rear.R[i, 3] = sin(rear.q[5])*Ax[i] + cos(rear.q[5])*Lz[i];
    rear.Wp[i, 1] = Ax[i];
    rear.Wp[i, 2] = 0;
    rear.Wp[i, 3] = 0;
    rear.Wp[i, 5] = Ly[i];
    rear.Wp[i, 6] = 0;
  end for;
  rear.Wp[1, 4] = 0;
  rear.Wp[2, 4] = 0;
  rear.Wp[3, 4] = 1;
  rear.w = rear.Wp*rear.u;
  // der(Ax) = u_psi Ay, der(Ly) = (u_psi e_z + u_phi Ax) x Ly = -u_psi cos(phi) Ax + u_phi Lz (u_phi = u[1])
  rear.al0 = rear.u[1]*u_psi*Ay + u_theta*(-u_psi*cos(rear.q[1])*Ax + rear.u[1]*Lz);
  // Rear contact: rolling without slip determines the motion of the rear axle
  rearContact.B = zeros(3, n);
  rearContact.b0 = zeros(3);
  rearContact.p[3] = 0;
  // Front contact: the dependent speeds
  Bi = frontContact.B*S;
  Bd = frontContact.B*D;
  Bd*Ad = -Bi;
  Bd*ad0 = -frontContact.b0;
  u_psi = Ad[1, :]*ui;
  u_theta = Ad[2, :]*ui;
  u_F = Ad[3, :]*ui;
  T = S + D*Ad;
  // Kane's equations reduced to the independent speeds
  // rear is a connector of the extending assembly itself (an outside connector there): its flows
  // are the sums over the bodies connected to it
  Mt = rear.M;
  for k in 2:n loop
    ft[k] = rear.f[k];
  end for;
  fe = ft - Mt*(D*ad0);
  Mr = transpose(T)*Mt*T;
  fr = transpose(T)*fe;
  Mr*dui = fr;
  u_psi_dot = Ad[1, :]*dui + ad0[1];
  u_theta_dot = Ad[2, :]*dui + ad0[2];
  u_F_dot = Ad[3, :]*dui + ad0[3];
  // Outputs
  v = rearContact.v[1]*cos(rear.q[4]) + rearContact.v[2]*sin(rear.q[4]);
  Mu = Mt*rear.u;
  uRow[1, :] = rear.u;
  K2 = uRow*Mu;
  E = 0.5*K2[1] + rear.Ep;
  residual = frontContact.p[3];
  annotation(Documentation(info = "<html>
<p>The root of the generalized-coordinate components for a bicycle (Kane's method), common to
<a href=\"modelica://Bicycle.Mechanics.Ground\">Ground</a> (the bicycle alone, <code>n = 6</code>) and
<a href=\"modelica://Bicycle.Mechanics.Rider.Ground\">Rider.Ground</a> (with the rider's hip hinge,
<code>n = 7</code>). It owns the configuration of the bicycle (position <code>x, y</code> of the rear
contact point; yaw <code>psi</code>, roll <code>phi</code>, pitch <code>theta</code> of the rear frame;
steer <code>delta</code>; wheel angles <code>thetaR, thetaF</code>) and its independent speeds
<code>u_phi, u_delta, u_R</code>, through the connector <code>rear</code> (<code>q</code>,
<code>u</code>); the extending class declares these states and the inputs (<code>T_phi</code>, ...)
in the order of its FMU (pymoca 0.12 lists a class's own elements before the inherited ones, so
states declared here would come after the extending class's lean angle) and binds them to
<code>rear.q</code>, <code>rear.u</code>, <code>dui</code> and <code>ft[1]</code>. The generalized speeds are
<code>u = {u_phi, u_delta, u_R, u_psi, u_theta, u_F, ...}</code> and
<code>q = {phi, delta, thetaR, psi, theta, thetaF, ...}</code> with <code>der(q) = u</code>; the
coordinates from 7 to <code>n</code> are further independent ones, declared by the extending class,
which also gives the selectors <code>S</code> (the columns of the <code>ni = n - 3</code> independent
speeds <code>ui</code>) and <code>D</code> (those of the dependent speeds <code>u_psi, u_theta,
u_F</code>), with <code>u = S*ui + D*ud</code>.</p>
<p>The connector <code>rear</code> gives the rear frame's orientation <code>R = Rz(psi) Rx(phi)
Ry(theta)</code> and its angular velocity; the rear wheel connected to it and to
<code>rearContact</code> determines the motion of the rear axle, because the ground imposes its
rolling rows <code>B = 0</code>, <code>b0 = 0</code>. The front wheel's rows
<code>Bi*ui + Bd*ud = 0</code> determine the dependent speeds <code>ud = Ad*ui</code>
(<code>Bd*Ad = -Bi</code>) and their acceleration remainder (<code>Bd*ad0 = -b0</code>). With
<code>u = T*ui</code>, <code>T = S + D*Ad</code>, Kane's equations of the constrained system are
<code>T'*Mt*T*der(ui) = T'*(ft - Mt*D*ad0)</code>, where <code>Mt</code> and <code>ft</code>
are the sums over all bodies arriving through <code>rear</code>. The roll torque <code>T_phi</code>
(on the rear frame about the yaw frame's x axis) is the generalized force of the roll coordinate.
The energy <code>E</code> is the kinetic energy <code>u'*Mt*u/2</code> plus the potential energy that
the components report through the connector (gravity, springs).</p>
<p>The pitch is integrated with the velocity form of the holonomic constraint; its initial value
solves the initial equation <code>residual = 0</code> (the front contact point on the ground), starting
from <code>theta_guess</code>.</p>
<p>Why a model to extend: a bicycle assembly <code>extends</code> a root (rather than containing an
instance of it) so that the coordinates are the top-level variables <code>phi</code>,
<code>delta</code>, ... of the FMU, the names its users and tools refer to.</p>
</html>"));
end PartialGround;
