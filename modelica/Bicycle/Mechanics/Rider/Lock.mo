within Bicycle.Mechanics.Rider;
model Lock "Locks the generalized speed selected by sel: passes the kinematics on, replaces the speed's row and column of the generalized mass matrix and forces beyond it by J*der(u_k) = 0"
  constant Integer n = 7 "Number of generalized speeds";
  constant Real sel[n] = {0, 0, 0, 0, 0, 0, 1} "Selects the locked speed (the unit vector of its index; default: the lean speed of Rider.Ground)";
  parameter Bicycle.Units.MomentOfInertia J = 1 "Coefficient of the lock's equation J*der(u_k) = 0 (any positive value gives the same motion)";
  Bicycle.Mechanics.Interfaces.Frame frame_a(n = n) "Frame on the root side";
  Bicycle.Mechanics.Interfaces.Frame frame_b(n = n) "Same frame on the side of the locked joint and the bodies beyond it";
equation
  frame_b.R = frame_a.R;
  frame_b.r = frame_a.r;
  frame_b.w = frame_a.w;
  frame_b.Wp = frame_a.Wp;
  frame_b.al0 = frame_a.al0;
  frame_b.Vp = frame_a.Vp;
  frame_b.a0 = frame_a.a0;
  frame_b.q = frame_a.q;
  frame_b.u = frame_a.u;
  // Row and column k of the bodies beyond are dropped (1 - sel[i]), the lock's own row is J*der(u_k) = 0
  for i in 1:n loop
    frame_a.M[i, 1] = -(1 - sel[i])*(1 - sel[1])*frame_b.M[i, 1] + J*sel[i]*sel[1];
    frame_a.M[i, 2] = -(1 - sel[i])*(1 - sel[2])*frame_b.M[i, 2] + J*sel[i]*sel[2];
    frame_a.M[i, 3] = -(1 - sel[i])*(1 - sel[3])*frame_b.M[i, 3] + J*sel[i]*sel[3];
    frame_a.M[i, 4] = -(1 - sel[i])*(1 - sel[4])*frame_b.M[i, 4] + J*sel[i]*sel[4];
    frame_a.M[i, 5] = -(1 - sel[i])*(1 - sel[5])*frame_b.M[i, 5] + J*sel[i]*sel[5];
    frame_a.M[i, 6] = -(1 - sel[i])*(1 - sel[6])*frame_b.M[i, 6] + J*sel[i]*sel[6];
    frame_a.M[i, 7] = -(1 - sel[i])*(1 - sel[7])*frame_b.M[i, 7] + J*sel[i]*sel[7];
    frame_a.f[i] = -(1 - sel[i])*frame_b.f[i];
  end for;
  0 = frame_a.Ep + frame_b.Ep;
  annotation(Documentation(info = "<html><p>Placed between a joint whose coordinate <code>k</code> (selected by
<code>sel</code>) is to be locked and the rest of the system. The bodies beyond it keep their
kinematics (they still turn with the coordinate), but the generalized mass matrix and forces they
contribute lose row and column <code>k</code>; the lock adds <code>J</code> on the diagonal. Kane's
equation of speed <code>k</code> becomes <code>J*der(u_k) = 0</code>: the joint keeps its rate (at rest:
its angle), and its torque, an internal torque pair that appears in no other equation, is the
reaction of the lock. Written for <code>n = 7</code> (the matrix columns are written out).</p></html>"));
end Lock;
