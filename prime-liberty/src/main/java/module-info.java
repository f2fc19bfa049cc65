/** The Liberty media: {@link dev.prime.liberty.LibertyCore}, chains fused by function composition. */
module dev.prime.liberty {
  requires transitive dev.prime;

  exports dev.prime.liberty;
}
