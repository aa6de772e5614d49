within Bicycle.Bodies;
model RearFrame "Rear frame B with the rigidly attached rider (Meijaard 2007, Table 1)"
  extends Bicycle.Bodies.PlanarRigidBody(m = 85, x = 0.3, z = -0.9, Ixx = 9.2, Ixz = 2.4, Iyy = 11, Izz = 2.8);
  annotation(Documentation(info = "<html>
<p>Rear frame including the rider, who sits rigidly on it with the hands off the handlebar.
Defaults: the benchmark bicycle of Meijaard et al. (2007) (xB, zB, mB, IBxx, IBxz, IByy, IBzz).</p>
</html>"));
end RearFrame;
